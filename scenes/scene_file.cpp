#include "scenes/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <stdexcept>

#include "sampler/diagnostics.h"
#include "sampler/io/image_io.h"
#include "sampler/io/input_file.h"
#include "sampler/io/round_trip.h"
#include "scenes/cornell_scene.h"
#include "scenes/default_scene.h"
#include "scenes/gltf_loader.h"
#include "scenes/gltf_scene.h"
#include "scenes/json_reader.h"
#include "scenes/material_factory.h"
#include "scenes/ply_loader.h"
#include "scenes/veach_mis_scene.h"

namespace fs = std::filesystem;

namespace nuld {

std::string resolveAssetRoot(const std::string &explicitRoot) {
  if (!explicitRoot.empty()) return explicitRoot;
  if (const char *env = std::getenv("NULD_ASSETS"); env && *env) return env;
  return (fs::path(NULD_SOURCE_DIR) / ".." / "shared" / "assets").lexically_normal().string();
}

namespace {

std::string assetPath(const std::string &root, const std::string &relative) {
  const fs::path p(relative);
  return p.is_absolute() ? p.string() : (fs::path(root) / p).string();
}

std::vector<TriangleMesh> loadMeshFile(const std::string &path, const JsonReader &field) {
  if (!fs::exists(path))
    throw std::runtime_error(field.file() + ": field '" + field.path() + "': mesh file '" + path +
                             "' does not exist (check --assets or NULD_ASSETS)");
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".glb" || ext == ".gltf") return loadGltf(path);
  if (ext == ".ply") return {loadPly(path)};
  field.fail("a .glb, .gltf or .ply file");
}

// A scene file's "gltf" entry: the path of an existing .gltf or .glb file.
std::string gltfFile(const JsonReader &field, const std::string &assetRoot) {
  const std::string file = assetPath(assetRoot, field.string());
  if (!isGltfPath(file)) field.fail("a .gltf or .glb file");
  if (!fs::exists(file))
    throw std::runtime_error(field.file() + ": field '" + field.path() + "': glTF file '" + file +
                             "' does not exist (check --assets or NULD_ASSETS)");
  return file;
}

// Embree traces in single precision: at 1e7 neighbouring floats are a unit
// apart, so geometry or a camera beyond cannot be resolved against a scene of
// unit scale; such coordinates are a unit or transform mistake.
constexpr double kCoordinateLimit = 1e7;

bool withinLimit(Vec3 p) {
  return std::abs(p.x) <= kCoordinateLimit && std::abs(p.y) <= kCoordinateLimit &&
         std::abs(p.z) <= kCoordinateLimit;
}

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "(" + string.
std::string describe(Vec3 p) {
  std::string text = "(";
  text += formatShort(p.x) + ", " + formatShort(p.y) + ", " + formatShort(p.z) + ")";
  return text;
}

// Refuses geometry out of range; warns about triangles of zero area in a
// mesh file (an exporter's leftovers: harmless, but the user should know;
// the built-in sphere's pole rows are degenerate by construction).
void checkGeometry(const TriangleMesh &mesh, const JsonReader &entry, const std::string &from) {
  for (const Vec3 &p : mesh.positions)
    if (!withinLimit(p))
      entry.refuse("mesh " + quotedInput(mesh.name) + from + " has a vertex at " + describe(p) +
                   ", outside +-1e7 on some axis (check the transform and the file's units)");
  if (from.empty()) return;
  std::size_t degenerate = 0;
  for (const auto &t : mesh.triangles) {
    const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    degenerate += !(length(cross(b - a, c - a)) > 0);
  }
  if (degenerate > 0)
    warning(entry.file() + ": mesh " + quotedInput(mesh.name) + from + ": " +
            std::to_string(degenerate) + " of " + std::to_string(mesh.triangles.size()) +
            " triangles have zero area (they are never hit)");
}

// Scale, then rotation about +Y, then translation.
void applyTransform(TriangleMesh &mesh, const JsonReader &t) {
  t.allowOnly({"scale", "rotate_y", "translate"});
  const double s = t.number("scale", 1.0, 1e-12, 1e12);
  const double a = t.number("rotate_y", 0.0) * std::numbers::pi / 180;
  const Vec3 d = t.has("translate") ? t["translate"].vec3() : Vec3{};
  const double c = std::cos(a), sn = std::sin(a);
  const auto rotate = [&](Vec3 v) { return Vec3{c * v.x + sn * v.z, v.y, -sn * v.x + c * v.z}; };
  for (Vec3 &p : mesh.positions) p = rotate(s * p) + d;
  for (Vec3 &n : mesh.normals) n = rotate(n);
}

// {"shape": "floor", "half_size": 20, "height": 0} or
// {"shape": "sphere", "center": [x, y, z], "radius": 1}.
TriangleMesh builtinShape(const JsonReader &entry) {
  const std::string shape = entry["shape"].string();
  if (shape == "floor")
    return makeFloor(entry.number("half_size", 20.0, 1e-9, 1e9), entry.number("height", 0.0),
                     "floor");
  if (shape == "sphere")
    return makeSphere(entry.has("center") ? entry["center"].vec3() : Vec3{},
                      entry.number("radius", 1.0, 1e-9, 1e9), 64, 128, "sphere");
  entry["shape"].fail("\"floor\" or \"sphere\"");
}

// An emitter's radiance times its scale ("radiance", "scale"); one that
// emits nothing is noted.
Rgb readEmission(const JsonReader &e, const std::string &what) {
  const Rgb radiance = e["radiance"].radiance() * e.number("scale", 1.0, 0, 1e30);
  if (radiance.isBlack())
    warning(e.file() + ": field '" + e.path() + "': " + what + " emits nothing (radiance 0)");
  return radiance;
}

// {"shape": "rectangle", "corner": [..], "edge0": [..], "edge1": [..]} (it
// faces cross(edge0, edge1)) or {"shape": "sphere", "center": [..],
// "radius": r}, with "radiance", "scale" and "two_sided".
AreaLight readEmitter(const JsonReader &e) {
  e.allowOnly({"shape", "corner", "edge0", "edge1", "center", "radius", "radiance", "scale",
               "two_sided", "comment"});
  const std::string shape = e["shape"].string();
  const bool twoSided = e.has("two_sided") && e["two_sided"].boolean();
  if (shape == "rectangle") {
    const Vec3 corner = e["corner"].vec3(), a = e["edge0"].vec3(), b = e["edge1"].vec3();
    const double la = length(a), lb = length(b);
    if (!(la > 0) || !(lb > 0) || !std::isfinite(la * lb))
      e[la > 0 ? "edge1" : "edge0"].refuse(
          "an edge of zero (or unbounded) length: the rectangle has no area");
    if (std::abs(dot(a, b)) > 1e-6 * la * lb)
      e["edge1"].refuse("not at right angles to edge0 (a rectangle's edges are orthogonal)");
    return AreaLight::rectangle(corner, a, b, readEmission(e, "the rectangle"), twoSided);
  }
  if (shape == "sphere")
    return AreaLight::sphere(e["center"].vec3(), e["radius"].number(1e-9, 1e9),
                             readEmission(e, "the sphere"), twoSided);
  e["shape"].fail("\"rectangle\" or \"sphere\"");
}

// A one-sided planar light whose every surface lies behind it lights nothing.
void noteFacingAway(const Scene &scene, const AreaLight &light, const JsonReader &e) {
  if (light.twoSided() || light.shape() == AreaLight::Shape::Sphere) return;
  const Vec3 n = light.normal(), p = light.boundsMin();
  for (const TriangleMesh &m : scene.geometry.meshes())
    for (const Vec3 q : m.positions)
      if (dot(q - p, n) > 0) return;
  warning(e.file() + ": field '" + e.path() +
          "': the light faces away from every surface of the scene (it lights nothing; "
          "\"two_sided\": true, or swap its edges)");
}

// A direction of any length, made unit: scaled by its largest component
// first, so that [1e-200, 0, 0] neither vanishes nor [1e200, 0, 0] overflows.
Vec3 readDirection(const JsonReader &field, const std::string &meaning) {
  const Vec3 v = field.vec3();
  const double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(largest > 0)) field.fail("a non-zero direction" + meaning);
  return normalize(v / largest);
}

CameraSettings readCamera(const JsonReader &c) {
  c.allowOnly({"eye", "look_at", "up", "fov", "mirror_x"});
  CameraSettings cam;
  cam.eye = c["eye"].vec3();
  cam.target = c["look_at"].vec3();
  if (c.has("up")) cam.up = readDirection(c["up"], "");
  cam.fovDegrees = c["fov"].number(1e-3, 179.9);
  if (c.has("mirror_x")) cam.mirrorX = c["mirror_x"].boolean();
  for (const char *key : {"eye", "look_at"})
    if (!withinLimit(c[key].vec3())) c[key].fail("a point within +-1e7 on every axis");
  if (!(length(cam.target - cam.eye) > 1e-6)) c["look_at"].fail("a point at least 1e-6 from 'eye'");
  const JsonReader up = c.has("up") ? c["up"] : c;
  if (!(length(cross(normalize(cam.target - cam.eye), cam.up)) > 1e-6))
    up.fail(c.has("up") ? "a direction not parallel to the view"
                        : "an 'up' direction: the default [0, 1, 0] is parallel to the view");
  return cam;
}

void readRender(const JsonReader &r, LoadedScene &out) {
  r.allowOnly({"spp", "integrator", "max_depth", "backend", "seed"});
  if (r.has("spp")) out.settings.spp = std::size_t(r["spp"].integer(1, 1 << 24));
  if (r.has("integrator")) {
    out.settings.integrator = r["integrator"].oneOf(kIntegratorNames);
  }
  if (r.has("max_depth")) out.settings.maxDepth = r["max_depth"].integer(1, kMaxDepthLimit);
  out.backend = r.string("backend", out.backend);
  if (r.has("seed")) out.seed = std::uint64_t(r["seed"].integer(0, 2147483647));
}

// The "meshes" of a scene file with the "materials" they name, and their
// emission: the scene's geometry.
void readMeshes(const JsonReader &root, const std::string &assetRoot, LobeChoice lobes,
                LoadedScene &out) {
  const std::string &path = out.name;
  // Meshes, and the materials they name.
  const JsonReader materials = root["materials"];
  const std::vector<std::string> materialNames = materials.keys();
  const std::set<std::string> known(materialNames.begin(), materialNames.end());
  std::map<std::string, std::shared_ptr<const Bsdf>> built;
  std::vector<TriangleMesh> meshes;
  std::vector<std::pair<std::size_t, JsonReader>> emitting;  // meshes with an "emission"
  const JsonReader meshList = root["meshes"];
  for (std::size_t i = 0; i < meshList.size(); ++i) {
    const JsonReader entry = meshList.at(i);
    entry.allowOnly({"file", "shape", "material", "skip", "transform", "half_size", "height",
                     "center", "radius", "emission"});
    if (entry.has("file") == entry.has("shape"))
      entry.fail("an object with either a \"file\" or a \"shape\" (floor or sphere)");
    const std::string file = entry.has("file") ? assetPath(assetRoot, entry["file"].string()) : "";
    const std::vector<std::string> skip =
        entry.has("skip") ? entry["skip"].strings() : std::vector<std::string>{};
    const std::string forced = entry.has("material") ? entry["material"].string() : "";
    if (!forced.empty() && !known.count(forced))
      entry["material"].fail("the name of an entry in 'materials'");
    for (TriangleMesh &mesh :
         entry.has("file") ? loadMeshFile(file, entry["file"]) : std::vector{builtinShape(entry)}) {
      const auto skipped = [&](const std::string &n) {
        return !n.empty() && std::find(skip.begin(), skip.end(), n) != skip.end();
      };
      if (skipped(mesh.material) || skipped(mesh.name)) continue;
      std::string name = forced;
      for (const std::string &candidate : {mesh.material, mesh.name, std::string("default")})
        if (name.empty() && !candidate.empty() && known.count(candidate)) name = candidate;
      if (name.empty())
        throw std::invalid_argument(path + ": no material for mesh '" + mesh.name +
                                    "' (material '" + mesh.material + "') from '" + file +
                                    "': add it to 'materials', add a \"default\" material, or "
                                    "set \"material\" in its 'meshes' entry");
      if (!built.count(name)) built[name] = makeMaterial(materials[name], lobes);
      if (entry.has("transform")) applyTransform(mesh, entry["transform"]);
      checkGeometry(mesh, entry, file.empty() ? "" : " from " + quotedInput(file));
      out.scene.materials.push_back(built[name]);
      if (entry.has("emission")) emitting.push_back({meshes.size(), entry["emission"]});
      meshes.push_back(std::move(mesh));
    }
  }
  if (meshes.empty()) meshList.fail("at least one mesh that is not skipped");
  out.scene.geometry = EmbreeScene(std::move(meshes));
  for (const auto &[mesh, e] : emitting) {
    e.allowOnly({"radiance", "scale", "two_sided"});
    addEmittingMesh(out.scene, mesh, readEmission(e, "the mesh"),
                    e.has("two_sided") && e["two_sided"].boolean());
    const auto &lights = out.scene.lights.triangles;
    if (std::none_of(lights.begin() + out.scene.lights.meshFirst[mesh], lights.end(),
                     [](const AreaLight &l) { return l.area() > 0; }))
      e.refuse("the mesh has no triangle of nonzero area to emit from");
  }
}

}  // namespace

const std::vector<std::string> &builtInScenes() {
  static const std::vector<std::string> names{"default", "stress", "cornell", "veach-mis"};
  return names;
}

std::string builtInSceneList() {
  std::string out;
  for (const std::string &n : builtInScenes()) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool isBuiltInScene(const std::string &name) {
  const auto &names = builtInScenes();
  return std::find(names.begin(), names.end(), name) != names.end();
}

LoadedScene loadScene(const std::string &path, const std::string &assetRoot,
                      const SceneChoices &choices) {
  if (path == "default") return makeDefaultScene(choices);
  if (path == "stress") return makeStressScene(choices);
  if (path == "cornell") return makeCornellScene();
  if (path == "veach-mis") return makeVeachMisScene(choices.lobes);
  const LobeChoice lobes = choices.lobes;
  if (isGltfPath(path)) {
    LoadedScene out = loadGltfScene(path, choices);
    finishLights(out.scene);
    return out;
  }

  requireInputFile(path, "the scene file");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the scene file");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception &e) {
    // Syntax errors and numbers beyond a double: the parser's reason,
    // without its "[json.exception.parse_error.101]" tag.
    std::string why = e.what();
    if (const auto tag = why.find("] "); why.rfind("[json.exception.", 0) == 0 && tag != why.npos)
      why = why.substr(tag + 2);
    throw std::invalid_argument(path + ": malformed JSON: " + why);
  }
  const JsonReader root(doc, path);
  root.allowOnly({"camera", "film", "render", "environment", "materials", "meshes", "emitters",
                  "gltf", "comment"});

  // A "gltf" file brings geometry, materials, lights and a camera; the
  // scene file's own camera, film and render settings override its.
  const bool fromGltf = root.has("gltf");
  LoadedScene out = fromGltf ? loadGltfScene(gltfFile(root["gltf"], assetRoot), choices)
                             : LoadedScene{path, Scene{EmbreeScene({}), {}, std::nullopt, {}}};
  out.name = path;
  if (!fromGltf || root.has("camera")) out.scene.camera = readCamera(root["camera"]);
  if (root.has("film")) {
    const JsonReader film = root["film"];
    film.allowOnly({"width", "height"});
    out.settings.width = film["width"].integer(1, 1 << 15);
    out.settings.height = film["height"].integer(1, 1 << 15);
  }
  if (root.has("render")) readRender(root["render"], out);

  if (fromGltf) {
    for (const char *key : {"meshes", "materials"})
      if (root.has(key))
        root[key].refuse("a scene with \"gltf\" takes its meshes and materials from the glTF file");
  } else {
    readMeshes(root, assetRoot, lobes, out);
  }
  if (root.has("emitters")) {
    const JsonReader list = root["emitters"];
    for (std::size_t i = 0; i < list.size(); ++i) {
      out.scene.lights.shapes.push_back(readEmitter(list.at(i)));
      noteFacingAway(out.scene, out.scene.lights.shapes.back(), list.at(i));
    }
  }

  if (root.has("environment")) {
    const JsonReader env = root["environment"];
    env.allowOnly({"file", "scale", "rotation", "up", "importance"});
    const std::string file = assetPath(assetRoot, env["file"].string());
    if (!fs::exists(file))
      throw std::runtime_error(path + ": field 'environment.file': '" + file +
                               "' does not exist (check --assets or NULD_ASSETS)");
    // A display image (8 bits, sRGB-encoded, clipped at 1) read as radiance
    // would light the scene wrongly without a word.
    if (imageEncoding(file) != ImageEncoding::Linear)
      throw std::runtime_error(path + ": field 'environment.file': '" + file +
                               "': expected a linear HDR map (.exr, .hdr or .pfm); a display "
                               "image is sRGB-encoded and clipped at 1 (convert it, e.g. oiiotool "
                               "IN --colorconvert sRGB linear -d float -o OUT.exr)");
    const Vec3 up = env.has("up") ? readDirection(env["up"], " (the map's zenith in the world)")
                                  : Vec3{0, 1, 0};
    // The file's importance is read (and checked) even where a choice
    // overrides it.
    const PixelWeight named =
        env.has("importance") ? env["importance"].oneOf(
                                    kImportanceNames, " (how a pixel's colour weighs its sampling)")
                              : kDefaultImportance;
    const PixelWeight weight = choices.importance.value_or(named);
    out.scene.environment.emplace(readImage(file), env.number("scale", 1.0, 0, 1e12),
                                  env.number("rotation", 0.0), file, up, weight);
  }
  finishLights(out.scene);
  return out;
}

}  // namespace nuld
