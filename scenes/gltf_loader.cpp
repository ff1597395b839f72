#include "scenes/gltf_loader.h"

// Declarations only: Debian's libtinygltf provides the implementation.
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "sampler/io/input_file.h"
#include "scenes/gltf_content.h"

namespace nuld {
namespace {

using gltf::Affine;
using gltf::fail;

// glTF buffers are little-endian; we read them with memcpy.
static_assert(std::endian::native == std::endian::little, "the glTF loader assumes little-endian");

bool allFinite(const std::vector<double> &v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

Affine localTransform(const std::string &path, const tinygltf::Node &node, int index) {
  const std::string what = "node " + std::to_string(index) + " ('" + node.name + "') ";
  Affine m;
  if (!node.matrix.empty()) {
    const std::vector<double> &a = node.matrix;  // column-major 4x4
    if (a.size() != 16 || !allFinite(a)) fail(path, what + "matrix is not 16 finite numbers");
    if (a[3] != 0 || a[7] != 0 || a[11] != 0 || a[15] != 1)
      fail(path, what + "matrix is not affine (last row must be 0 0 0 1)");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m.l[r][c] = a[4 * c + r];
    m.t = {a[12], a[13], a[14]};
    return m;
  }
  // T * R * S.
  const auto &t = node.translation, &q = node.rotation, &s = node.scale;
  if ((!t.empty() && t.size() != 3) || (!q.empty() && q.size() != 4) ||
      (!s.empty() && s.size() != 3) || !allFinite(t) || !allFinite(q) || !allFinite(s))
    fail(path, what + "translation, rotation or scale is not 3, 4, 3 finite numbers");
  if (!q.empty()) {
    // Normalized here: exporters write quaternions rounded to float.
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(n > 0)) fail(path, what + "rotation is a zero quaternion");
    const double x = q[0] / n, y = q[1] / n, z = q[2] / n, w = q[3] / n;
    m.l = {{{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}}};
  }
  if (!s.empty())
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m.l[r][c] *= s[c];
  if (!t.empty()) m.t = {t[0], t[1], t[2]};
  return m;
}

// --- Accessors -----------------------------------------------------------------

std::size_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

// One accessor's elements, checked to lie inside their buffer view and buffer.
struct AccessorData {
  const unsigned char *first = nullptr;  // element 0
  std::size_t stride = 0;                // bytes from one element to the next
  std::size_t count = 0;
  int componentType = 0;
  bool normalized = false;
};

// Reads one primitive's data; `where` names it in error messages.
class PrimitiveReader {
 public:
  PrimitiveReader(const std::string &path, const tinygltf::Model &model, std::string where)
      : path_(path), model_(model), where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string &what) const { nuld::fail(path_, where_ + what); }

  // `type` is TINYGLTF_TYPE_SCALAR, _VEC2 or _VEC3.
  AccessorData accessor(int index, const std::string &role, int type) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
      fail(role + " accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor &a = model_.accessors[index];
    const std::string what = role + " accessor " + std::to_string(index) + " ";
    if (a.sparse.isSparse) fail(what + "is sparse; sparse accessors are not supported");
    if (a.bufferView < 0) fail(what + "has no bufferView (all-zero accessors are not supported)");
    if (std::size_t(a.bufferView) >= model_.bufferViews.size())
      fail(what + "refers to missing bufferView " + std::to_string(a.bufferView));
    const tinygltf::BufferView &view = model_.bufferViews[a.bufferView];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
      fail(what + "uses a bufferView whose buffer " + std::to_string(view.buffer) +
           " does not exist");
    const std::vector<unsigned char> &buffer = model_.buffers[view.buffer].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      fail(what + "uses bufferView " + std::to_string(a.bufferView) + " (bytes " +
           std::to_string(view.byteOffset) + " + " + std::to_string(view.byteLength) +
           ") which exceeds its buffer of " + std::to_string(buffer.size()) + " bytes");
    const std::size_t components = type == TINYGLTF_TYPE_VEC3   ? 3
                                   : type == TINYGLTF_TYPE_VEC2 ? 2
                                                                : 1;
    if (a.type != type || componentSize(a.componentType) == 0)
      fail(what + "has the wrong type; expected " +
           (components == 3   ? "VEC3"
            : components == 2 ? "VEC2"
                              : "SCALAR"));
    const std::size_t elementSize = components * componentSize(a.componentType);
    const std::size_t stride = view.byteStride ? view.byteStride : elementSize;
    if (stride < elementSize)
      fail(what + "has byteStride " + std::to_string(stride) + ", smaller than its " +
           std::to_string(elementSize) + "-byte elements");
    // The last element must end inside the view; written to avoid overflow.
    const std::size_t room = view.byteLength;
    if (a.count > 0 && (a.byteOffset > room || room - a.byteOffset < elementSize ||
                        (a.count - 1) > (room - a.byteOffset - elementSize) / stride))
      fail(what + "(" + std::to_string(a.count) + " elements from byte " +
           std::to_string(a.byteOffset) + ") exceeds its bufferView of " + std::to_string(room) +
           " bytes");
    return {buffer.data() + view.byteOffset + a.byteOffset, stride, a.count, a.componentType,
            a.normalized};
  }

  // Texture coordinates: float, or unsigned byte or short normalized to [0, 1].
  std::vector<Point2> uvs(int index) const {
    const AccessorData d = accessor(index, "TEXCOORD_0", TINYGLTF_TYPE_VEC2);
    std::vector<Point2> out(d.count);
    const auto read = [&]<typename T>(T, double scale) {
      for (std::size_t i = 0; i < d.count; ++i) {
        T v[2];
        std::memcpy(v, d.first + i * d.stride, sizeof(v));
        out[i] = {v[0] * scale, v[1] * scale};
        if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y))
          fail("TEXCOORD_0 " + std::to_string(i) + " is not finite");
      }
    };
    const bool normalized = d.normalized;
    if (d.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
      read(float{}, 1.0);
    else if (normalized && d.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
      read(std::uint8_t{}, 1.0 / 255);
    else if (normalized && d.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
      read(std::uint16_t{}, 1.0 / 65535);
    else
      fail("TEXCOORD_0 accessor " + std::to_string(index) +
           " is neither float nor normalized unsigned byte or short");
    return out;
  }

  std::vector<Vec3> vec3s(int index, const std::string &role) const {
    const AccessorData d = accessor(index, role, TINYGLTF_TYPE_VEC3);
    if (d.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(role + " accessor " + std::to_string(index) +
           " is not float (quantized "
           "attributes are not supported)");
    std::vector<Vec3> out(d.count);
    for (std::size_t i = 0; i < d.count; ++i) {
      float v[3];
      std::memcpy(v, d.first + i * d.stride, sizeof(v));
      out[i] = {v[0], v[1], v[2]};
    }
    return out;
  }

  std::vector<std::uint32_t> indices(int index) const {
    const AccessorData d = accessor(index, "indices", TINYGLTF_TYPE_SCALAR);
    std::vector<std::uint32_t> out(d.count);
    const auto read = [&]<typename T>(T) {
      for (std::size_t i = 0; i < d.count; ++i) {
        T v;
        std::memcpy(&v, d.first + i * d.stride, sizeof(T));
        out[i] = v;
      }
    };
    switch (d.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: read(std::uint8_t{}); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: read(std::uint16_t{}); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: read(std::uint32_t{}); break;
      default: fail("indices accessor " + std::to_string(index) + " is not of an unsigned type");
    }
    return out;
  }

 private:
  const std::string &path_;
  const tinygltf::Model &model_;
  std::string where_;
};

// --- Meshes ----------------------------------------------------------------------

// One primitive placed by `world`; empty when it has no triangles.
TriangleMesh placePrimitive(const std::string &path, const tinygltf::Model &model,
                            const tinygltf::Node &node, int meshIndex, int primitiveIndex,
                            const Affine &world) {
  const tinygltf::Mesh &gltfMesh = model.meshes[meshIndex];
  const tinygltf::Primitive &prim = gltfMesh.primitives[primitiveIndex];
  const PrimitiveReader reader(path, model,
                               "mesh " + std::to_string(meshIndex) + " ('" + gltfMesh.name +
                                   "') primitive " + std::to_string(primitiveIndex) + ": ");

  TriangleMesh mesh;
  mesh.name = !gltfMesh.name.empty() ? gltfMesh.name
              : !node.name.empty()   ? node.name
                                     : "mesh" + std::to_string(meshIndex);
  if (prim.material >= 0) {
    if (std::size_t(prim.material) >= model.materials.size())
      reader.fail("material " + std::to_string(prim.material) + " does not exist");
    mesh.material = model.materials[prim.material].name;
  }

  const auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) reader.fail("has no POSITION attribute");
  mesh.positions = reader.vec3s(position->second, "POSITION");
  const std::size_t vertexCount = mesh.positions.size();
  if (const auto normal = prim.attributes.find("NORMAL"); normal != prim.attributes.end()) {
    mesh.normals = reader.vec3s(normal->second, "NORMAL");
    if (mesh.normals.size() != vertexCount)
      reader.fail("has " + std::to_string(mesh.normals.size()) + " normals for " +
                  std::to_string(vertexCount) + " positions");
  }
  if (const auto uv = prim.attributes.find("TEXCOORD_0"); uv != prim.attributes.end()) {
    mesh.uvs = reader.uvs(uv->second);
    if (mesh.uvs.size() != vertexCount)
      reader.fail("has " + std::to_string(mesh.uvs.size()) + " texture coordinates for " +
                  std::to_string(vertexCount) + " positions");
  }

  std::vector<std::uint32_t> indices;
  if (prim.indices >= 0) {
    indices = reader.indices(prim.indices);
    for (const std::uint32_t i : indices)
      if (i >= vertexCount)
        reader.fail("index " + std::to_string(i) + " is out of range (" +
                    std::to_string(vertexCount) + " vertices)");
  } else {
    indices.resize(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) indices[i] = std::uint32_t(i);
  }
  if (indices.size() % 3 != 0)
    reader.fail(std::to_string(indices.size()) + " vertex indices is not a multiple of 3");

  // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners.
  const bool mirror = world.det() < 0;
  mesh.triangles.reserve(indices.size() / 3);
  for (std::size_t i = 0; i < indices.size(); i += 3) {
    if (mirror)
      mesh.triangles.push_back({indices[i], indices[i + 2], indices[i + 1]});
    else
      mesh.triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
  }

  for (std::size_t i = 0; i < vertexCount; ++i) {
    mesh.positions[i] = world.point(mesh.positions[i]);
    if (!isFinite(mesh.positions[i]))
      reader.fail("position " + std::to_string(i) + " is not finite");
  }
  const Affine normalMatrix = world.normalMatrix();
  for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
    const Vec3 n = normalMatrix.linear(mesh.normals[i]);
    const double len = length(n);
    if (!(len > 0) || !std::isfinite(len))
      reader.fail("normal " + std::to_string(i) + " is zero or not finite");
    mesh.normals[i] = n / len;
  }
  return mesh;
}

// The root nodes to draw: the default scene's, else the first scene's, else
// (no scenes at all) every node that is nobody's child.
std::vector<int> rootNodes(const tinygltf::Model &model) {
  if (!model.scenes.empty()) {
    const bool valid =
        model.defaultScene >= 0 && std::size_t(model.defaultScene) < model.scenes.size();
    return model.scenes[valid ? model.defaultScene : 0].nodes;
  }
  std::vector<bool> isChild(model.nodes.size(), false);
  for (const tinygltf::Node &n : model.nodes)
    for (const int c : n.children)
      if (c >= 0 && std::size_t(c) < isChild.size()) isChild[c] = true;
  std::vector<int> roots;
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (!isChild[i]) roots.push_back(int(i));
  return roots;
}

// The meshes, with each one's material, and the first perspective camera
// and the punctual lights the nodes place.
void collectNodes(const std::string &path, const tinygltf::Model &model, GltfFile &out) {
  // Depth first with an explicit stack, in file order. glTF node hierarchies are
  // strict trees, so a node reached twice means a cycle or a shared child.
  std::vector<bool> visited(model.nodes.size(), false);
  std::vector<std::pair<int, Affine>> stack;
  const std::vector<int> roots = rootNodes(model);
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, Affine{});
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || std::size_t(index) >= model.nodes.size())
      fail(path, "node " + std::to_string(index) + " does not exist");
    if (visited[index])
      fail(path, "node " + std::to_string(index) +
                     " is reached twice; the node hierarchy must be a tree");
    visited[index] = true;
    const tinygltf::Node &node = model.nodes[index];
    const Affine world = parent * localTransform(path, node, index);
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      stack.emplace_back(*c, world);
    gltf::placeCameraAndLight(path, model, index, world, out);

    // A zero scale hides a node: nothing to draw, and no normal matrix.
    if (node.mesh < 0 || world.det() == 0) continue;
    if (std::size_t(node.mesh) >= model.meshes.size())
      fail(path, "node " + std::to_string(index) + " refers to missing mesh " +
                     std::to_string(node.mesh));
    const tinygltf::Mesh &mesh = model.meshes[node.mesh];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const int mode = mesh.primitives[p].mode;
      // Points and lines have no surface to render; strips and fans do, so
      // dropping them silently would lose geometry.
      if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) continue;
      if (mode != TINYGLTF_MODE_TRIANGLES)
        fail(path, "mesh " + std::to_string(node.mesh) + " ('" + mesh.name + "') primitive " +
                       std::to_string(p) + " has mode " + std::to_string(mode) +
                       "; only TRIANGLES (4) is supported");
      TriangleMesh placed = placePrimitive(path, model, node, node.mesh, int(p), world);
      if (placed.triangles.empty()) continue;
      out.meshes.push_back(std::move(placed));
      out.meshMaterials.push_back(mesh.primitives[p].material);
    }
  }
}

bool hasExtension(const std::string &path, const char *ext) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e == ext;
}

// Geometry only: leave images unread.
bool skipImage(tinygltf::Image *, const int, std::string *, std::string *, int, int,
               const unsigned char *, int, void *) {
  return true;
}

// Keeps an image's encoded bytes for GltfFile::images, decoded later only
// where a material that is drawn reads it.
bool keepImage(tinygltf::Image *, const int index, std::string *, std::string *, int, int,
               const unsigned char *bytes, int size, void *images) {
  auto &out = *static_cast<std::vector<GltfImage> *>(images);
  if (index < 0) return true;
  if (out.size() <= std::size_t(index)) out.resize(std::size_t(index) + 1);
  if (bytes && size > 0) out[index].bytes.assign(bytes, bytes + size);
  return true;
}

GltfFile load(const std::string &path, bool withImages) {
  const bool binary = hasExtension(path, ".glb");
  if (!binary && !hasExtension(path, ".gltf"))
    fail(path, "unknown glTF file extension; expected .gltf or .glb");

  requireInputFile(path, "glTF file");
  tinygltf::TinyGLTF gltf;
  GltfFile file;
  if (withImages)
    gltf.SetImageLoader(&keepImage, &file.images);
  else
    gltf.SetImageLoader(&skipImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = binary ? gltf.LoadBinaryFromFile(&model, &err, &warn, path)
                         : gltf.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
    const bool readable = std::ifstream(path, std::ios::binary).good();
    fail(path,
         std::string(readable ? "cannot parse glTF file: " : "cannot open glTF file: ") + err);
  }
  for (const std::string &ext : model.extensionsRequired)
    if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" ||
        ext == "KHR_mesh_quantization")
      fail(path, "requires glTF extension " + ext + ", which is not supported");

  collectNodes(path, model, file);
  if (file.meshes.empty()) fail(path, "no triangle meshes in the scene");
  if (withImages) gltf::readMaterials(path, model, file);
  return file;
}

}  // namespace

bool isGltfPath(const std::string &path) {
  return hasExtension(path, ".glb") || hasExtension(path, ".gltf");
}

GltfFile loadGltfFile(const std::string &path) { return load(path, true); }

std::vector<TriangleMesh> loadGltf(const std::string &path) {
  return std::move(load(path, false).meshes);
}

}  // namespace nuld
