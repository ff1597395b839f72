// NeuralGenerator's model files: the metadata that rebuilds the network
// (metadata(), load()) and the weights (toModelFile(), loadWeights()).

#include <cstdio>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/model_file.h"
#include "sampler/neural/network.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

constexpr const char *kFormat = "nuld-neural-generator";
constexpr int kVersion = 1;
// The metadata 'base' of each randomization (files from before the Owen base
// all say the rotated one's).
constexpr const char *kRotatedBase = "sobol rotated by z";
constexpr const char *kOwenBase = "sobol owen-scrambled by a hash of z";

std::string joinSizes(const std::vector<std::size_t> &sizes) {
  std::string s;
  for (const std::size_t n : sizes) s += (s.empty() ? "" : ",") + std::to_string(n);
  return s;
}

}  // namespace

std::map<std::string, std::string> NeuralGenerator::metadata() const {
  std::map<std::string, std::string> m = {
      {"format", kFormat},
      {"arch", toString(settings_.arch)},
      {"version", std::to_string(kVersion)},
      {"n", std::to_string(settings_.n)},
      {"dimension", "2"},
      {"domain", toString(domain())},
      {"family", settings_.family},
      {"gamma_dimension", std::to_string(gammaDimension())},
      {"hidden", std::to_string(settings_.hidden)},
      {"sigma", formatRoundTrip(settings_.sigma)},
      {"encoding_dims", std::to_string(settings_.encodingDims)},
      {"z_harmonics", std::to_string(settings_.zHarmonics)},
      {"offset_range", formatRoundTrip(settings_.offsetRange)},
      {"seed", std::to_string(settings_.seed)},
      {"base", settings_.base == BaseRandomization::Owen ? kOwenBase : kRotatedBase},
      {"mapping", settings_.mapped ? "mapped" : "unmapped"}};
  if (settings_.arch == NetworkArch::Graph) {
    m["neighbours"] = std::to_string(settings_.neighbours);
    m["rounds"] = std::to_string(settings_.rounds);
    m["position_harmonics"] = std::to_string(settings_.positionHarmonics);
    m["stages"] = std::to_string(settings_.stages);
    m["discrepancy_gradient"] = settings_.discrepancyGradient ? "1" : "0";
  }
  // Only for several sizes, so single-size files keep their metadata.
  if (!settings_.trainingNs.empty()) m["training_n"] = joinSizes(settings_.trainingNs);
  return m;
}

ModelFile NeuralGenerator::toModelFile(const std::map<std::string, std::string> &extra) const {
  ModelFile file;
  file.metadata = extra;
  for (const auto &[k, v] : metadata()) file.metadata[k] = v;
  auto add = [&](const std::string &name, const torch::Tensor &t) {
    const torch::Tensor f = t.detach().to(torch::kFloat32).contiguous();
    file.tensors.push_back(
        {name, std::vector<std::int64_t>(f.sizes().begin(), f.sizes().end()),
         std::vector<float>(f.data_ptr<float>(), f.data_ptr<float>() + f.numel())});
  };
  for (const auto &item : net_->module().named_buffers()) add(item.key(), item.value());
  for (const auto &item : net_->module().named_parameters()) add(item.key(), item.value());
  return file;
}

void NeuralGenerator::save(const std::string &path,
                           const std::map<std::string, std::string> &extra) const {
  writeModelFile(path, toModelFile(extra));
}

void NeuralGenerator::loadWeights(const ModelFile &file, const std::string &path) {
  torch::NoGradGuard noGrad;
  auto fill = [&](const std::string &name, torch::Tensor &t) {
    const ModelTensor &mt = file.tensor(name, path);
    if (std::vector<std::int64_t>(t.sizes().begin(), t.sizes().end()) != mt.shape)
      throw std::runtime_error(path + ": tensor '" + name +
                               "' has the wrong shape for the network its metadata describes");
    t.copy_(torch::from_blob(const_cast<float *>(mt.data.data()), t.sizes(), torch::kFloat32));
  };
  for (auto &item : net_->module().named_buffers()) fill(item.key(), item.value());
  for (auto &item : net_->module().named_parameters()) fill(item.key(), item.value());
}

NeuralGenerator NeuralGenerator::load(const std::string &path) {
  const ModelFile file = readModelFile(path);
  if (file.metadata.count("format") == 0 || file.metadata.at("format") != kFormat)
    throw std::runtime_error(path + ": not a neural generator model (metadata 'format' is not '" +
                             kFormat + "')");
  if (file.value("version", path) != std::to_string(kVersion))
    throw std::runtime_error(path + ": model version " + file.value("version", path) +
                             ", this program reads version " + std::to_string(kVersion));
  auto number = [&](const std::string &key) {
    const std::string &v = file.value(key, path);
    try {
      std::size_t used = 0;
      const double x = std::stod(v, &used);
      if (used != v.size()) throw std::invalid_argument(v);
      return x;
    } catch (const std::exception &) {
      throw std::runtime_error(path + ": model metadata '" + key + "' is not a number: '" + v +
                               "'");
    }
  };
  NeuralSettings s;
  // Files from before the graph generator have no 'arch': the supplement's.
  if (file.metadata.count("arch")) {
    try {
      s.arch = parseNetworkArch(file.metadata.at("arch"));
    } catch (const std::invalid_argument &e) {
      throw std::runtime_error(path + ": model metadata 'arch': " + e.what());
    }
  }
  if (s.arch == NetworkArch::Graph) {
    s.neighbours = int(number("neighbours"));
    s.rounds = int(number("rounds"));
    s.positionHarmonics = int(number("position_harmonics"));
    s.stages = int(number("stages"));
    s.discrepancyGradient = number("discrepancy_gradient") != 0;
    if (file.metadata.count("training_n")) {
      try {
        s.trainingNs = parseSizeList("model metadata 'training_n'", file.metadata.at("training_n"));
      } catch (const std::invalid_argument &e) {
        throw std::runtime_error(path + ": " + e.what());
      }
    }
  }
  if (file.metadata.count("base")) {
    const std::string &base = file.metadata.at("base");
    if (base == kOwenBase)
      s.base = BaseRandomization::Owen;
    else if (base != kRotatedBase)
      throw std::runtime_error(path + ": model metadata 'base' is '" + base + "', expected '" +
                               kRotatedBase + "' or '" + kOwenBase + "'");
  }
  s.n = std::size_t(number("n"));
  s.hidden = int(number("hidden"));
  s.sigma = number("sigma");
  s.encodingDims = int(number("encoding_dims"));
  // Files from before these options have no keys: no harmonics, full range.
  if (file.metadata.count("z_harmonics")) s.zHarmonics = int(number("z_harmonics"));
  if (file.metadata.count("offset_range")) s.offsetRange = number("offset_range");
  try {
    s.seed = std::stoull(file.value("seed", path));
  } catch (const std::logic_error &) {
    throw std::runtime_error(path + ": model metadata 'seed' is not an unsigned integer");
  }
  s.family = file.value("family", path);
  const std::string &mapping = file.value("mapping", path);
  if (mapping != "mapped" && mapping != "unmapped")
    throw std::runtime_error(path + ": model metadata 'mapping' is '" + mapping +
                             "', expected mapped or unmapped");
  s.mapped = mapping == "mapped";
  try {
    NeuralGenerator gen(std::move(s));
    gen.loadWeights(file, path);
    gen.fileMetadata_ = file.metadata;
    return gen;
  } catch (const std::invalid_argument &e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace nuld
