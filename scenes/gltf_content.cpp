#include "scenes/gltf_content.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "sampler/io/round_trip.h"

namespace nuld::gltf {
namespace {

// The material extensions whose factors nuld maps (gltf_scene.cpp).
const std::set<std::string> kMaterialExtensions = {
    "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_clearcoat",
    "KHR_materials_specular", "KHR_materials_emissive_strength"};

bool isHandledExtension(const std::string &e) {
  return kMaterialExtensions.count(e) || e == "KHR_lights_punctual";
}

// Counts of what the file holds and nuld does not use, by phrase.
class Unused {
 public:
  void add(const std::string &what, std::size_t n = 1) { counts_[what] += n; }
  std::vector<std::string> phrases() const {
    std::vector<std::string> out;
    for (const auto &[what, n] : counts_) out.push_back(what + " (" + std::to_string(n) + ")");
    return out;
  }

 private:
  std::map<std::string, std::size_t> counts_;
};

std::string materialName(const tinygltf::Model &model, int index) {
  return "material " + std::to_string(index) + " ('" + model.materials[index].name + "') ";
}

// A factor of the file: `n` numbers each finite and in [lo, hi].
std::vector<double> factor(const std::string &path, const std::string &what,
                           const std::vector<double> &v, std::size_t n, double lo, double hi) {
  if (v.size() != n)
    fail(path,
         what + "has " + std::to_string(v.size()) + " numbers; expected " + std::to_string(n));
  for (const double x : v)
    if (!(x >= lo && x <= hi))
      fail(path, what + "holds " + formatShort(x) + "; expected numbers in [" + formatShort(lo) +
                     ", " + formatShort(hi) + "]");
  return v;
}

// An extension's number `key`, `fallback` when absent.
double extensionNumber(const std::string &path, const std::string &what, const tinygltf::Value &ext,
                       const char *key, double fallback, double lo, double hi) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value &v = ext.Get(key);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
  if (!(x >= lo && x <= hi))
    fail(path, what + key + " is not a number in [" + formatShort(lo) + ", " +
                   (std::isinf(hi) ? std::string("inf") : formatShort(hi)) + "]");
  return x;
}

// The texture a material names, or -1 (none, or one read through a
// coordinate set other than TEXCOORD_0, which is noted).
int textureRef(const std::string &path, const tinygltf::Model &model, const std::string &what,
               const tinygltf::TextureInfo &info, Unused &unused) {
  if (info.index < 0) return -1;
  if (std::size_t(info.index) >= model.textures.size())
    fail(path, what + "names texture " + std::to_string(info.index) + ", which does not exist");
  if (info.texCoord != 0) {
    unused.add("textures read through a TEXCOORD set other than 0 (left out)");
    return -1;
  }
  if (info.extensions.count("KHR_texture_transform"))
    unused.add("texture transforms (KHR_texture_transform; textures read untransformed)");
  return info.index;
}

Texture::Wrap wrapMode(int mode) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Texture::Wrap::Clamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Texture::Wrap::Mirror;
    default: return Texture::Wrap::Repeat;
  }
}

GltfMaterial readMaterial(const std::string &path, const tinygltf::Model &model, int index,
                          Unused &unused) {
  const tinygltf::Material &m = model.materials[index];
  const std::string what = materialName(model, index);
  const tinygltf::PbrMetallicRoughness &pbr = m.pbrMetallicRoughness;
  GltfMaterial out;
  out.name = m.name;
  const std::vector<double> base =
      factor(path, what + "baseColorFactor ", pbr.baseColorFactor, 4, 0, 1);
  out.baseColor = {base[0], base[1], base[2]};
  out.alpha = base[3];
  out.metallic = factor(path, what + "metallicFactor ", {pbr.metallicFactor}, 1, 0, 1)[0];
  out.roughness = factor(path, what + "roughnessFactor ", {pbr.roughnessFactor}, 1, 0, 1)[0];
  out.baseColorTexture =
      textureRef(path, model, what + "baseColorTexture ", pbr.baseColorTexture, unused);
  out.metallicRoughnessTexture = textureRef(path, model, what + "metallicRoughnessTexture ",
                                            pbr.metallicRoughnessTexture, unused);
  const std::vector<double> e =
      m.emissiveFactor.empty() ? std::vector<double>{0, 0, 0}
                               : factor(path, what + "emissiveFactor ", m.emissiveFactor, 3, 0, 1);
  out.emissive = {e[0], e[1], e[2]};
  out.doubleSided = m.doubleSided;
  if (m.alphaMode != "OPAQUE" || out.alpha < 1)
    unused.add("materials with alpha or alphaMode (rendered opaque)");
  if (m.normalTexture.index >= 0) unused.add("normal textures");
  if (m.occlusionTexture.index >= 0) unused.add("occlusion textures");
  if (m.emissiveTexture.index >= 0) unused.add("emissive textures (the factor alone emits)");

  const auto ext = [&](const char *name) -> const tinygltf::Value * {
    const auto it = m.extensions.find(name);
    return it == m.extensions.end() ? nullptr : &it->second;
  };
  const auto textureIn = [&](const tinygltf::Value &x, const char *key, const char *phrase) {
    if (x.Has(key)) unused.add(phrase);
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (const auto *x = ext("KHR_materials_emissive_strength"))
    out.emissive *= extensionNumber(path, what + "KHR_materials_emissive_strength.", *x,
                                    "emissiveStrength", 1, 0, 1e30);
  if (const auto *x = ext("KHR_materials_transmission")) {
    out.transmission = extensionNumber(path, what + "KHR_materials_transmission.", *x,
                                       "transmissionFactor", 0, 0, 1);
    textureIn(*x, "transmissionTexture", "transmission textures");
  }
  if (const auto *x = ext("KHR_materials_ior"))
    out.ior = extensionNumber(path, what + "KHR_materials_ior.", *x, "ior", 1.5, 1, kInf);
  if (const auto *x = ext("KHR_materials_clearcoat")) {
    const std::string w = what + "KHR_materials_clearcoat.";
    out.clearcoat = extensionNumber(path, w, *x, "clearcoatFactor", 0, 0, 1);
    out.clearcoatRoughness = extensionNumber(path, w, *x, "clearcoatRoughnessFactor", 0, 0, 1);
    textureIn(*x, "clearcoatTexture", "clearcoat textures");
    textureIn(*x, "clearcoatRoughnessTexture", "clearcoat roughness textures");
    textureIn(*x, "clearcoatNormalTexture", "clearcoat normal textures");
  }
  if (const auto *x = ext("KHR_materials_specular")) {
    const std::string w = what + "KHR_materials_specular.";
    out.specular = extensionNumber(path, w, *x, "specularFactor", 1, 0, 1);
    textureIn(*x, "specularTexture", "specular textures");
    textureIn(*x, "specularColorTexture", "specular colour textures");
    // F0 times the colour factor: a grey one scales the specular as the
    // factor does; a tint (Disney's follows the base colour only) is
    // noted and its largest component kept.
    if (x->Has("specularColorFactor")) {
      const tinygltf::Value &c = x->Get("specularColorFactor");
      double rgb[3] = {1, 1, 1};
      for (int k = 0; k < 3; ++k) {
        const bool ok = c.IsArray() && c.ArrayLen() == 3 && c.Get(k).IsNumber();
        rgb[k] = ok ? c.Get(k).GetNumberAsDouble() : std::nan("");
        if (!(rgb[k] >= 0 && rgb[k] < 1e30))
          fail(path, w + "specularColorFactor is not 3 numbers >= 0");
      }
      out.specular *= std::max({rgb[0], rgb[1], rgb[2]});
      if (rgb[0] != rgb[1] || rgb[1] != rgb[2])
        unused.add("specular colour tints (KHR_materials_specular; their largest component kept)");
    }
  }
  for (const auto &[name, value] : m.extensions)
    if (!kMaterialExtensions.count(name)) unused.add("materials with extension " + name);
  return out;
}

}  // namespace

void placeCameraAndLight(const std::string &path, const tinygltf::Model &model, int index,
                         const Affine &world, GltfFile &out) {
  const tinygltf::Node &node = model.nodes[index];
  const std::string what = "node " + std::to_string(index) + " ('" + node.name + "') ";
  const Vec3 origin = world.point({});
  const auto towards = [&](Vec3 v, const char *role) {
    const Vec3 d = world.linear(v);
    const double len = length(d);
    if (!(len > 0) || !std::isfinite(len))
      fail(path, what + "has a singular transform; its " + role + " has no direction");
    return d / len;
  };
  if (node.camera >= 0) {
    if (std::size_t(node.camera) >= model.cameras.size())
      fail(path, what + "refers to missing camera " + std::to_string(node.camera));
    const tinygltf::Camera &c = model.cameras[node.camera];
    if (c.type != "perspective") {
      out.unused.push_back("an orthographic camera (node " + std::to_string(index) + ")");
    } else if (out.camera) {
      out.unused.push_back("a further perspective camera (node " + std::to_string(index) + ")");
    } else {
      const double yfov = c.perspective.yfov;
      if (!(yfov > 1e-5 && yfov < std::numbers::pi - 1e-3))
        fail(path, "camera " + std::to_string(node.camera) + " ('" + c.name +
                       "') yfov is not in (0, pi) radians");
      const double aspect = c.perspective.aspectRatio;
      if (!(aspect >= 0 && aspect < 1e4))
        fail(path, "camera " + std::to_string(node.camera) + " ('" + c.name +
                       "') aspectRatio is not a number in (0, 1e4)");
      out.camera = GltfCamera{origin, towards({0, 0, -1}, "camera"), towards({0, 1, 0}, "camera"),
                              yfov, aspect};
    }
  }
  const auto ext = node.extensions.find("KHR_lights_punctual");
  if (ext == node.extensions.end() || !ext->second.Has("light")) return;
  const tinygltf::Value &l = ext->second.Get("light");
  const int light = l.IsNumber() ? int(l.GetNumberAsDouble()) : -1;
  if (light < 0 || std::size_t(light) >= model.lights.size())
    fail(path, what + "KHR_lights_punctual.light names light " + std::to_string(light) +
                   ", which does not exist");
  const tinygltf::Light &src = model.lights[light];
  const std::string lw = "light " + std::to_string(light) + " ('" + src.name + "') ";
  const std::vector<double> colour = src.color.empty()
                                         ? std::vector<double>{1, 1, 1}
                                         : factor(path, lw + "color ", src.color, 3, 0, 1);
  if (!(src.intensity >= 0 && src.intensity < 1e30))
    fail(path, lw + "intensity is not a number in [0, 1e30]");
  if (!(src.range >= 0) || std::isinf(src.range)) fail(path, lw + "range is not a number > 0");
  const Rgb value = src.intensity * Rgb{colour[0], colour[1], colour[2]};
  const double range = src.range > 0 ? src.range : PunctualLight::kNoRange;
  if (src.type == "point") {
    out.lights.push_back(PunctualLight::point(origin, value, range));
  } else if (src.type == "spot") {
    const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
    if (!(inner >= 0 && inner < outer && outer <= std::numbers::pi / 2))
      fail(path, lw + "spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle "
                      "<= pi/2");
    out.lights.push_back(
        PunctualLight::spot(origin, towards({0, 0, -1}, "light"), value, inner, outer, range));
  } else if (src.type == "directional") {
    out.lights.push_back(PunctualLight::directional(towards({0, 0, -1}, "light"), value));
  } else {
    fail(path, lw + "type is '" + src.type + "'; expected point, spot or directional");
  }
}

void readMaterials(const std::string &path, const tinygltf::Model &model, GltfFile &out) {
  Unused unused;
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    out.materials.push_back(readMaterial(path, model, int(i), unused));
  for (std::size_t i = 0; i < out.meshMaterials.size(); ++i)
    if (const int m = out.meshMaterials[i]; m >= 0 && std::size_t(m) >= model.materials.size())
      fail(path, "mesh '" + out.meshes[i].name + "' names material " + std::to_string(m) +
                     ", which does not exist");
  for (std::size_t i = 0; i < model.textures.size(); ++i) {
    const tinygltf::Texture &t = model.textures[i];
    const std::string what = "texture " + std::to_string(i) + " ('" + t.name + "') ";
    GltfTexture tex;
    // No image is -1: only a texture a drawn material reads needs one
    // (gltf_scene.cpp refuses it there).
    const bool hasImage = t.source >= 0 && std::size_t(t.source) < model.images.size();
    tex.image = hasImage ? t.source : -1;
    if (t.sampler >= 0) {
      if (std::size_t(t.sampler) >= model.samplers.size())
        fail(path, what + "names sampler " + std::to_string(t.sampler) + ", which does not exist");
      tex.wrapU = wrapMode(model.samplers[t.sampler].wrapS);
      tex.wrapV = wrapMode(model.samplers[t.sampler].wrapT);
    }
    for (const auto &[name, value] : t.extensions)
      unused.add("textures with extension " + name + " (their source image is read)");
    out.textures.push_back(tex);
  }
  out.images.resize(std::max(out.images.size(), model.images.size()));
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image &img = model.images[i];
    out.images[i].name =
        "image " + std::to_string(i) +
        (img.uri.empty() || img.uri.rfind("data:", 0) == 0 ? "" : " ('" + img.uri + "')");
  }

  if (!model.animations.empty()) unused.add("animations", model.animations.size());
  if (!model.skins.empty()) unused.add("skins", model.skins.size());
  for (const tinygltf::Mesh &mesh : model.meshes)
    for (const tinygltf::Primitive &p : mesh.primitives) {
      if (!p.targets.empty()) unused.add("primitives with morph targets");
      if (p.attributes.count("COLOR_0")) unused.add("primitives with vertex colours");
      if (p.mode >= TINYGLTF_MODE_POINTS && p.mode <= TINYGLTF_MODE_LINE_STRIP)
        unused.add("point or line primitives (no surface to render)");
    }
  std::set<std::string> extensions(model.extensionsUsed.begin(), model.extensionsUsed.end());
  for (const std::string &e : extensions)
    // Material extensions are counted by material above.
    if (!isHandledExtension(e) && e != "KHR_texture_transform" && e.rfind("KHR_materials_", 0) != 0)
      unused.add("extension " + e);
  for (std::string &phrase : unused.phrases()) out.unused.push_back(std::move(phrase));
}

}  // namespace nuld::gltf
