#include "scenes/gltf_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include "materials/disney.h"
#include "sampler/diagnostics.h"
#include "scenes/gltf_loader.h"
#include "scenes/mesh_bounds.h"

namespace nuld {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kFilmWidth = 512;

// The Disney parameters of a glTF material, its textures aside.
DisneyParams disneyParams(const std::string &path, const GltfMaterial &m, const std::string &what) {
  DisneyParams p;
  p.baseColor = m.baseColor;
  p.metallic = m.metallic;
  p.roughness = m.roughness;
  // F0 = 0.08 specular (Burley 2012); glTF's dielectric F0 is that of its
  // ior, scaled by KHR_materials_specular's factor.
  const double f0 = std::pow((m.ior - 1) / (m.ior + 1), 2);
  p.specular = std::clamp(m.specular * f0 / 0.08, 0.0, 1.0);
  p.clearcoat = m.clearcoat;
  // Disney's coat has GGX alpha 0.1 - 0.099 gloss; glTF's, roughness^2.
  const double alpha = m.clearcoatRoughness * m.clearcoatRoughness;
  p.clearcoatGloss = std::clamp((0.1 - alpha) / 0.099, 0.0, 1.0);
  if (m.transmission > 0) {
    if (!(m.ior > 1 && m.ior <= 4))
      throw std::runtime_error(path + ": " + what +
                               "KHR_materials_ior.ior must be in (1, 4] for a material that "
                               "transmits (nuld's dielectric)");
    p.specTrans = m.transmission;
    p.ior = m.ior;
  }
  return p;
}

// Makes each texture once, decoded as its role wants.
class TextureMaker {
 public:
  TextureMaker(const std::string &path, const GltfFile &file) : path_(path), file_(file) {}

  std::shared_ptr<const Texture> make(int index, Texture::Encoding encoding) {
    if (index < 0) return nullptr;
    auto &slot = made_[{index, encoding}];
    if (slot) return slot;
    const GltfTexture &t = file_.textures[index];
    const std::string what = path_ + ": texture " + std::to_string(index) + " ";
    if (t.image < 0 || std::size_t(t.image) >= file_.images.size())
      throw std::runtime_error(what + "has no source image");
    const GltfImage &img = file_.images[t.image];
    if (img.bytes.empty())
      throw std::runtime_error(what + "reads " + img.name +
                               ", which could not be read (a missing file?)");
    // The format by its signature: the decoder picks it by the name.
    const bool png = img.bytes.size() > 4 && img.bytes[0] == 0x89 && img.bytes[1] == 'P';
    const bool jpeg = img.bytes.size() > 3 && img.bytes[0] == 0xff && img.bytes[1] == 0xd8;
    if (!png && !jpeg)
      throw std::runtime_error(what + "reads " + img.name + ", which is neither PNG nor JPEG");
    slot = std::make_shared<const Texture>(
        readImageBytes(path_ + ": " + img.name + (png ? ".png" : ".jpg"), img.bytes), encoding,
        t.wrapU, t.wrapV);
    return slot;
  }

 private:
  const std::string &path_;
  const GltfFile &file_;
  std::map<std::pair<int, Texture::Encoding>, std::shared_ptr<const Texture>> made_;
};

// The film and camera of the file's camera, else the default view.
void placeCamera(const GltfFile &file, LoadedScene &out) {
  CameraSettings &cam = out.scene.camera;
  if (file.camera) {
    const GltfCamera &c = *file.camera;
    const double aspect = c.aspectRatio > 0 ? c.aspectRatio : 1.0;
    out.settings.width = kFilmWidth;
    out.settings.height = std::max(1, int(std::lround(kFilmWidth / aspect)));
    cam.eye = c.eye;
    cam.target = c.eye + c.forward;
    cam.up = c.up;
    // nuld's field of view spans the image's shorter side.
    const double fov =
        aspect >= 1 ? c.yfovRadians : 2 * std::atan(std::tan(c.yfovRadians / 2) * aspect);
    cam.fovDegrees = fov * 180 / kPi;
    return;
  }
  const MeshBounds b = meshBounds(file.meshes);
  const Vec3 centre = 0.5 * (b.lo + b.hi);
  const double radius = std::max(0.5 * length(b.hi - b.lo), 1e-6);
  cam.fovDegrees = 40;
  cam.target = centre;
  cam.eye = centre + Vec3{0, 0, 1.1 * radius / std::sin(20 * kPi / 180)};
  cam.up = {0, 1, 0};
  out.settings.width = out.settings.height = kFilmWidth;
}

std::string joined(const std::vector<std::string> &parts) {
  std::string out;
  for (const std::string &p : parts) out += (out.empty() ? "" : "; ") + p;
  return out;
}

}  // namespace

LoadedScene loadGltfScene(const std::string &path, const SceneChoices &choices) {
  GltfFile file = loadGltfFile(path);
  std::vector<std::string> notes = file.unused;
  LoadedScene out{path, Scene{EmbreeScene({}), {}, std::nullopt, {}}};
  out.scene.lobeChoice = choices.lobes;
  placeCamera(file, out);

  // Each glTF material once (index -1: glTF's default material).
  const GltfMaterial fallback{};
  std::map<int, std::shared_ptr<const Bsdf>> materials;
  std::map<int, std::shared_ptr<const TexturedDisney>> textured;
  TextureMaker textures(path, file);
  std::vector<std::pair<std::size_t, const GltfMaterial *>> emitting;
  bool uvsMissing = false;
  for (std::size_t i = 0; i < file.meshes.size(); ++i) {
    const int index = file.meshMaterials[i];
    const GltfMaterial &m = index >= 0 ? file.materials[index] : fallback;
    const std::string what =
        index >= 0 ? "material " + std::to_string(index) + " ('" + m.name + "') " : "";
    if (!materials.count(index)) {
      const DisneyParams params = disneyParams(path, m, what);
      materials[index] = std::make_shared<const DisneyBrdf>(params, choices.lobes);
      if (m.baseColorTexture >= 0 || m.metallicRoughnessTexture >= 0) {
        auto t = std::make_shared<TexturedDisney>();
        t->factors = params;
        t->lobes = choices.lobes;
        t->baseColor = textures.make(m.baseColorTexture, Texture::Encoding::Srgb);
        t->metallicRoughness = textures.make(m.metallicRoughnessTexture, Texture::Encoding::Linear);
        textured[index] = std::move(t);
      } else {
        textured[index] = nullptr;
      }
    }
    out.scene.materials.push_back(materials[index]);
    const auto &t = textured[index];
    if (t) {
      if (out.scene.textured.size() < file.meshes.size())
        out.scene.textured.resize(file.meshes.size());
      out.scene.textured[i] = t;
      uvsMissing = uvsMissing || file.meshes[i].uvs.empty();
    }
    if (!m.emissive.isBlack()) emitting.push_back({i, &m});
  }
  if (uvsMissing)
    notes.push_back("textured meshes without TEXCOORD_0 (their textures read at (0, 0))");
  out.scene.geometry = EmbreeScene(std::move(file.meshes));
  for (const auto &[mesh, m] : emitting)
    addEmittingMesh(out.scene, mesh, m->emissive, m->doubleSided);
  out.scene.lights.punctual = std::move(file.lights);
  if (!notes.empty()) warning(path + ": not used by nuld: " + joined(notes));
  return out;
}

}  // namespace nuld
