// Mesh loaders: PLY (ascii and both binary byte orders) and glTF node
// hierarchies against hand-computed values, clear errors naming the file, and
// the real assets when they are present.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "scenes/gltf_loader.h"
#include "scenes/mesh_bounds.h"
#include "scenes/ply_loader.h"
#include "tests/common/expect_error.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;
using Triangle = std::array<std::uint32_t, 3>;

const fs::path kData = fs::path(NULD_TEST_DATA_DIR) / "scenes";
const fs::path kAssets = fs::path(NULD_SOURCE_DIR) / ".." / "shared" / "assets";

using test::TempDir;

// The message of the std::runtime_error that `load` throws.
std::string errorOf(const std::function<void()> &load) {
  return test::errorMessage<std::runtime_error>(load);
}

void expectError(const std::function<void()> &load, const std::string &path,
                 const std::string &what) {
  const std::string message = errorOf(load);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find(what), std::string::npos) << message;
}

void expectNear(Vec3 a, Vec3 b, double tol = 1e-6) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

std::size_t triangleCount(const std::vector<TriangleMesh> &meshes) {
  std::size_t n = 0;
  for (const TriangleMesh &m : meshes) n += m.triangles.size();
  return n;
}

// --- PLY -------------------------------------------------------------------------

// The content of tri_quad_normals_ascii.ply.
const std::vector<Vec3> kPlyPositions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0.5, 0}};
const std::vector<Vec3> kPlyNormals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0.6, 0.8}};
const std::vector<Triangle> kPlyTriangles = {{0, 1, 2}, {1, 3, 4}, {1, 4, 2},
                                             {0, 1, 3}, {0, 3, 4}, {0, 4, 2}};

void expectFixtureMesh(const TriangleMesh &m) {
  ASSERT_EQ(m.positions.size(), kPlyPositions.size());
  ASSERT_EQ(m.normals.size(), kPlyNormals.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    expectNear(m.positions[i], kPlyPositions[i], 0);
    expectNear(m.normals[i], kPlyNormals[i], 1e-7);
  }
  EXPECT_EQ(m.triangles, kPlyTriangles);
  EXPECT_EQ(m.material, "");
}

TEST(PlyLoader, AsciiPolygonsNormalsAndSkippedData) {
  const TriangleMesh m = loadPly((kData / "tri_quad_normals_ascii.ply").string());
  EXPECT_EQ(m.name, "tri_quad_normals_ascii");
  expectFixtureMesh(m);
}

TEST(PlyLoader, AsciiFaceBeforeVertexWithoutNormals) {
  const TriangleMesh m = loadPly((kData / "tri_no_normals_ascii.ply").string());
  EXPECT_EQ(m.name, "tri_no_normals_ascii");
  ASSERT_EQ(m.positions.size(), 3u);
  expectNear(m.positions[0], {0.5, -1.25, 300}, 0);
  expectNear(m.positions[1], {1, 2, 3}, 0);
  expectNear(m.positions[2], {-4, 5.5, 6}, 0);
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{2, 1, 0}}));
}

// Writes the fixture's mesh as binary PLY in either byte order, with the
// same kinds of extra data as the ascii file, in other types.
class BinaryPly {
 public:
  explicit BinaryPly(bool bigEndian) : big_(bigEndian) {}

  std::string bytes() {
    std::string out =
        std::string("ply\nformat ") + (big_ ? "binary_big_endian" : "binary_little_endian") +
        " 1.0\n"
        "element vertex 5\n"
        "property double x\nproperty float y\nproperty float z\n"
        "property ushort extra\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "element edge 2\nproperty list int16 uint8 vertex_pair\nproperty char crease\n"
        "element face 3\nproperty list uchar int vertex_indices\n"
        "property float quality\n"
        "end_header\n";
    body_.clear();
    for (std::size_t i = 0; i < kPlyPositions.size(); ++i) {
      const Vec3 p = kPlyPositions[i];
      put(p.x);
      put(float(p.y));
      put(float(p.z));
      put(std::uint16_t(1000 + i));
      const Vec3 n = kPlyNormals[i] * (i + 1.0);  // not unit length
      put(float(n.x));
      put(float(n.y));
      put(float(n.z));
    }
    for (int e = 0; e < 2; ++e) {
      put(std::int16_t(2));
      put(std::uint8_t(e));
      put(std::uint8_t(e + 1));
      put(std::int8_t(-1));
    }
    const std::vector<std::vector<int>> faces = {{0, 1, 2}, {1, 3, 4, 2}, {0, 1, 3, 4, 2}};
    for (const std::vector<int> &face : faces) {
      put(std::uint8_t(face.size()));
      for (const int v : face) put(std::int32_t(v));
      put(0.5f);
    }
    return out + body_;
  }

 private:
  template <typename T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_ == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    body_.append(b, sizeof(T));
  }

  bool big_;
  std::string body_;
};

TEST(PlyLoader, BinaryLittleAndBigEndianMatchAscii) {
  const TempDir dir;
  for (const bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    const std::string path = dir.write(big ? "be.ply" : "le.ply", BinaryPly(big).bytes());
    const TriangleMesh m = loadPly(path);
    EXPECT_EQ(m.name, big ? "be" : "le");
    expectFixtureMesh(m);
  }
}

TEST(PlyLoader, TruncatedDataNamesFileAndElement) {
  expectError([] { loadPly((kData / "truncated_ascii.ply").string()); }, "truncated_ascii.ply",
              "element 'vertex' item 4 of 4: truncated data");
  const TempDir dir;
  std::string bytes = BinaryPly(false).bytes();
  bytes.resize(bytes.size() - 3);
  const std::string path = dir.write("cut.ply", bytes);
  expectError([&] { loadPly(path); }, path, "element 'face' item 3 of 3: truncated data");
}

TEST(PlyLoader, BadHeadersNameFileAndExpectation) {
  expectError([] { loadPly((kData / "bad_header.ply").string()); }, "bad_header.ply",
              "expected format ascii, binary_little_endian or binary_big_endian");

  const TempDir dir;
  const std::string vertex = "element vertex 1\nproperty float x\nproperty float y\n";
  const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
  const struct {
    std::string name, text, expected;
  } cases[] = {
      {"not_ply.ply", "hello\n", "not a PLY file"},
      {"no_end.ply", "ply\nformat ascii 1.0\n" + vertex, "expected an 'end_header' line"},
      {"no_format.ply", "ply\n" + vertex + "property float z\n" + face + "end_header\n",
       "no 'format' line"},
      {"orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
       "expected an 'element' line before the first 'property'"},
      {"bad_type.ply", "ply\nformat ascii 1.0\n" + vertex + "property real z\nend_header\n",
       "expected a type"},
      {"bad_count.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
       "non-negative integer COUNT"},
      {"float_count.ply",
       "ply\nformat ascii 1.0\nelement face 1\nproperty list float int "
       "vertex_indices\nend_header\n",
       "integer COUNT_TYPE"},
      {"no_z.ply", "ply\nformat ascii 1.0\n" + vertex + face + "end_header\n0 0\n3 0 0 0\n",
       "lacks property x, y or z"},
      {"some_normals.ply",
       "ply\nformat ascii 1.0\n" + vertex + "property float z\nproperty float nx\n" + face +
           "end_header\n",
       "only some of nx, ny, nz"},
      {"no_faces.ply", "ply\nformat ascii 1.0\n" + vertex + "property float z\nend_header\n0 0 0\n",
       "no 'face' element"},
      {"float_indices.ply",
       "ply\nformat ascii 1.0\n" + vertex +
           "property float z\nelement face 1\nproperty list uchar float vertex_indices\n"
           "end_header\n",
       "must be a list of integers"},
  };
  for (const auto &c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.write(c.name, c.text);
    expectError([&] { loadPly(path); }, path, c.expected);
  }
}

TEST(PlyLoader, BadDataNamesFileAndItem) {
  const TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  const struct {
    std::string name, text, expected;
  } cases[] = {
      {"out_of_range.ply", header + vertices + "3 0 1 3\n", "index 3 is out of range"},
      {"negative.ply", header + vertices + "3 0 -1 2\n", "vertex index -1 is out of range"},
      {"two_corners.ply", header + vertices + "2 0 1\n", "face has 2 vertices"},
      {"not_integer.ply", header + vertices + "3 0 1.5 2\n", "'1.5' is not an integer"},
      {"not_number.ply", header + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "'zero' is not a number"},
      {"nan.ply", header + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
       "element 'vertex' item 2 of 3: position is not finite"},
  };
  for (const auto &c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.write(c.name, c.text);
    expectError([&] { loadPly(path); }, path, c.expected);
  }
  const std::string zeroNormal =
      dir.write("zero_normal.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                "0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n3 0 1 2\n");
  expectError([&] { loadPly(zeroNormal); }, zeroNormal, "normal is zero or not finite");
}

TEST(PlyLoader, KeepsDegenerateTrianglesAndReadsCrlfHeaders) {
  const TempDir dir;
  const std::string path =
      dir.write("crlf.ply",
                "ply\r\nformat ascii 1.0\r\ncomment written on Windows\r\nelement vertex 3\r\n"
                "property float x\r\nproperty float y\r\nproperty float z\r\n"
                "element face 2\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n3 1 1 2\r\n");
  const TriangleMesh m = loadPly(path);
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}, {1, 1, 2}}));
}

TEST(PlyLoader, MissingFile) {
  expectError([] { loadPly("/nonexistent/mesh.ply"); }, "/nonexistent/mesh.ply",
              "cannot open PLY file");
}

// --- glTF ------------------------------------------------------------------------

const std::string kGltfFixture = (kData / "hierarchy.gltf").string();

TEST(GltfLoader, NodeHierarchyMatchesHandComputedValues) {
  const std::vector<TriangleMesh> meshes = loadGltf(kGltfFixture);
  // Depth-first node order; the LINES primitive and the zero-scale node add nothing.
  ASSERT_EQ(meshes.size(), 5u);

  // root (T = (1,2,3), S = 2) > child (R = 90 degrees about z, S = (1,3,1)):
  // p -> 2 R diag(1,3,1) p + (1,2,3); normals by the inverse transpose.
  const TriangleMesh &tri = meshes[0];
  EXPECT_EQ(tri.name, "tri_u8");
  EXPECT_EQ(tri.material, "red");
  ASSERT_EQ(tri.positions.size(), 3u);
  expectNear(tri.positions[0], {1, 2, 3});
  expectNear(tri.positions[1], {1, 4, 3});
  expectNear(tri.positions[2], {-5, 2, 3});
  ASSERT_EQ(tri.normals.size(), 3u);
  expectNear(tri.normals[0], {0, 0, 1});
  expectNear(tri.normals[1], {-1, 0, 0});
  expectNear(tri.normals[2], Vec3{-1, 3, 0} / std::sqrt(10.0));
  EXPECT_EQ(tri.triangles, (std::vector<Triangle>{{0, 1, 2}}));

  // Non-uniform scale (2,1,1): the slanted normal (1,1,0) becomes (1,2,0).
  const TriangleMesh &stretched = meshes[1];
  EXPECT_EQ(stretched.name, "quad_u16");
  EXPECT_EQ(stretched.material, "blue");
  expectNear(stretched.positions[2], {2, 1, 0});
  for (const Vec3 n : stretched.normals) expectNear(n, Vec3{1, 2, 0} / std::sqrt(5.0));
  EXPECT_EQ(stretched.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));

  // A mirroring matrix (x -> -x, then +5 z) flips the winding; the geometric
  // normal of the flipped triangles agrees with the transformed normals.
  const TriangleMesh &mirrored = meshes[2];
  EXPECT_EQ(mirrored.name, "quad_u32");
  EXPECT_EQ(mirrored.material, "");
  expectNear(mirrored.positions[1], {-1, 0, 5});
  expectNear(mirrored.positions[2], {-1, 1, 5});
  EXPECT_EQ(mirrored.triangles, (std::vector<Triangle>{{0, 2, 1}, {0, 3, 2}}));
  for (const Triangle &t : mirrored.triangles) {
    const Vec3 &p0 = mirrored.positions[t[0]], &p1 = mirrored.positions[t[1]],
               &p2 = mirrored.positions[t[2]];
    EXPECT_GT(dot(cross(p1 - p0, p2 - p0), mirrored.normals[t[0]]), 0);
  }

  // The same mesh instanced again by another node.
  const TriangleMesh &again = meshes[3];
  EXPECT_EQ(again.name, "quad_u32");
  expectNear(again.positions[2], {11, 1, 0});
  EXPECT_EQ(again.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));

  // Non-indexed, unnamed mesh: named after its node.
  const TriangleMesh &plain = meshes[4];
  EXPECT_EQ(plain.name, "plain_node");
  EXPECT_TRUE(plain.normals.empty());
  EXPECT_EQ(plain.triangles, (std::vector<Triangle>{{0, 1, 2}}));

  const MeshBounds b = meshBounds(meshes);
  expectNear(b.lo, {-5, 0, 0});
  expectNear(b.hi, {11, 4, 5});
}

// The fixture's JSON, edited by `edit`, written to a temp dir and loaded.
std::string errorOfEditedFixture(const TempDir &dir, const std::string &name,
                                 const std::function<void(nlohmann::json &)> &edit,
                                 std::string *path) {
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(kGltfFixture));
  edit(doc);
  *path = dir.write(name, doc.dump());
  return errorOf([&] { loadGltf(*path); });
}

TEST(GltfLoader, CorruptFilesGiveClearErrors) {
  const TempDir dir;
  using json = nlohmann::json;
  const struct {
    std::string name;
    std::function<void(json &)> edit;
    std::string expected;
  } cases[] = {
      {"count.gltf", [](json &d) { d["accessors"][3]["count"] = 1000; },
       "accessor 3 (1000 elements from byte 0) exceeds its bufferView of 48 bytes"},
      {"offset.gltf", [](json &d) { d["accessors"][4]["byteOffset"] = 1u << 31; },
       "exceeds its bufferView"},
      {"stride.gltf", [](json &d) { d["bufferViews"][0]["byteStride"] = 8; },
       "byteStride 8, smaller than its 12-byte elements"},
      {"index.gltf",
       [](json &d) {
         d["accessors"][0]["count"] = 2;
         d["accessors"][1]["count"] = 2;
       },
       "index 2 is out of range (2 vertices)"},
      {"normals.gltf", [](json &d) { d["accessors"][1]["count"] = 2; },
       "has 2 normals for 3 positions"},
      {"ushort.gltf", [](json &d) { d["accessors"][3]["componentType"] = 5123; },
       "POSITION accessor 3 is not float"},
      {"vec2.gltf", [](json &d) { d["accessors"][3]["type"] = "VEC2"; },
       "POSITION accessor 3 has the wrong type; expected VEC3"},
      {"signed.gltf", [](json &d) { d["accessors"][2]["componentType"] = 5120; },
       "indices accessor 2 is not of an unsigned type"},
      {"partial.gltf", [](json &d) { d["accessors"][5]["count"] = 5; },
       "5 vertex indices is not a multiple of 3"},
      {"strip.gltf", [](json &d) { d["meshes"][0]["primitives"][0]["mode"] = 5; },
       "has mode 5; only TRIANGLES (4) is supported"},
      {"cycle.gltf", [](json &d) { d["nodes"][1]["children"] = json::array({0}); },
       "node 0 is reached twice; the node hierarchy must be a tree"},
      {"no_node.gltf", [](json &d) { d["nodes"][0]["children"] = json::array({42}); },
       "node 42 does not exist"},
      {"no_position.gltf",
       [](json &d) { d["meshes"][3]["primitives"][0]["attributes"].erase("POSITION"); },
       "mesh 3 ('') primitive 0: has no POSITION attribute"},
      {"matrix.gltf", [](json &d) { d["nodes"][3]["matrix"][3] = 1; }, "matrix is not affine"},
      {"no_triangles.gltf", [](json &d) { d["scenes"][0]["nodes"] = json::array({6}); },
       "no triangle meshes"},
  };
  for (const auto &c : cases) {
    SCOPED_TRACE(c.name);
    std::string path;
    const std::string message = errorOfEditedFixture(dir, c.name, c.edit, &path);
    EXPECT_NE(message.find(path + ": "), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
  // Caught by tinygltf or by us; either way a clear error naming the file.
  std::string path;
  const std::string big = errorOfEditedFixture(
      dir, "view.gltf", [](json &d) { d["bufferViews"][2]["byteLength"] = 4096; }, &path);
  EXPECT_EQ(big.rfind(path + ": ", 0), 0u) << big;
}

TEST(GltfLoader, UnreadableFilesNameTheFile) {
  expectError([] { loadGltf("/nonexistent/scene.glb"); }, "/nonexistent/scene.glb: cannot open",
              "/nonexistent/scene.glb");
  expectError([] { loadGltf("/nonexistent/scene.gltf"); }, "/nonexistent/scene.gltf: cannot open",
              "/nonexistent/scene.gltf");
  const TempDir dir;
  const std::string broken = dir.write("broken.gltf", "{\"asset\": ");
  expectError([&] { loadGltf(broken); }, broken + ": cannot parse glTF file", "");
  const std::string notGlb = dir.write("text.glb", "ply\n");
  expectError([&] { loadGltf(notGlb); }, notGlb + ": cannot parse glTF file", "");
  expectError([] { loadGltf("mesh.obj"); }, "mesh.obj", "expected .gltf or .glb");
}

// --- The project's assets (PROVENANCE.md), when present ---------------------------

bool haveAssets(std::initializer_list<const char *> files) {
  return std::all_of(files.begin(), files.end(),
                     [](const char *f) { return fs::exists(kAssets / f); });
}

TEST(MeshAssets, LteOrb) {
  if (!haveAssets({"lte_orb/lte_orb.glb"})) GTEST_SKIP() << "no lte_orb under " << kAssets;
  const std::vector<TriangleMesh> meshes = loadGltf((kAssets / "lte_orb/lte_orb.glb").string());
  EXPECT_EQ(meshes.size(), 7u);
  EXPECT_EQ(triangleCount(meshes), 191970u);
  std::set<std::string> materials;
  for (const TriangleMesh &m : meshes) {
    materials.insert(m.material);
    EXPECT_EQ(m.normals.size(), m.positions.size()) << m.name;
  }
  EXPECT_EQ(materials, (std::set<std::string>{"OuterMat", "InnerMat", "BackGroundMat", "LTELogo",
                                              "Material"}));
  // The emitter quad, placed by its node's rotation and translation, is
  // pbrt-v4's lte-orb area light: y from 3.2046 to 3.2518, facing down.
  const auto emitter = std::find_if(meshes.begin(), meshes.end(),
                                    [](const TriangleMesh &m) { return m.material == "Material"; });
  ASSERT_NE(emitter, meshes.end());
  EXPECT_EQ(emitter->triangles.size(), 2u);
  const MeshBounds b = meshBounds(*emitter);
  expectNear(b.lo, {-1, 3.204597, -0.999721}, 1e-5);
  expectNear(b.hi, {1, 3.251826, 0.999721}, 1e-5);
  EXPECT_LT(emitter->normals[0].y, -0.99);
}

TEST(MeshAssets, Dragon) {
  if (!haveAssets({"dragon/stanford_dragon_100k.glb"}))
    GTEST_SKIP() << "no dragon under " << kAssets;
  const std::vector<TriangleMesh> meshes =
      loadGltf((kAssets / "dragon/stanford_dragon_100k.glb").string());
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 100000u);
  EXPECT_EQ(meshes[0].normals.size(), meshes[0].positions.size());
  const MeshBounds b = meshBounds(meshes);
  expectNear(b.lo, {-7.05, 0, -3.15}, 0.01);
  expectNear(b.hi, {7.05, 9.94, 3.15}, 0.01);
}

TEST(MeshAssets, CausticCupAndFloor) {
  if (!haveAssets({"cup/caustic_glass_cup.glb", "cup/geometry_mesh_00002.ply"}))
    GTEST_SKIP() << "no cup under " << kAssets;
  const std::vector<TriangleMesh> cup = loadGltf((kAssets / "cup/caustic_glass_cup.glb").string());
  ASSERT_EQ(cup.size(), 1u);
  EXPECT_EQ(cup[0].triangles.size(), 88064u);
  EXPECT_EQ(cup[0].normals.size(), cup[0].positions.size());
  const TriangleMesh floor = loadPly((kAssets / "cup/geometry_mesh_00002.ply").string());
  EXPECT_EQ(floor.name, "geometry_mesh_00002");
  EXPECT_EQ(floor.triangles.size(), 2u);
  // Both in pbrt's world frame: the cup stands on the floor, inside it.
  const MeshBounds c = meshBounds(cup), f = meshBounds(floor);
  EXPECT_NEAR(f.lo.y, f.hi.y, 1e-6);
  EXPECT_GT(c.lo.y, f.hi.y);
  EXPECT_LT(c.lo.y - f.hi.y, 0.05);
  EXPECT_TRUE(c.lo.x > f.lo.x && c.hi.x < f.hi.x && c.lo.z > f.lo.z && c.hi.z < f.hi.z);
}

}  // namespace
}  // namespace nuld
