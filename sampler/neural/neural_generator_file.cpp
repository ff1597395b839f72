// NeuralGenerator's model files: the metadata that rebuilds the network
// (metadata(), load()) and the weights (toModelFile(), loadWeights()).

#include <cstdio>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/model_file.h"
#include "sampler/neural/model_metadata.h"
#include "sampler/neural/neural_generator.h"

namespace nuld {
namespace {

std::string joinSizes(const std::vector<std::size_t> &sizes) {
  std::string s;
  for (const std::size_t n : sizes) s += (s.empty() ? "" : ",") + std::to_string(n);
  return s;
}

}  // namespace

std::map<std::string, std::string> NeuralGenerator::metadata() const {
  std::map<std::string, std::string> m = {
      {"format", kModelFormat},
      {"arch", toString(settings_.arch)},
      {"version", std::to_string(kModelVersion)},
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
      {"base", settings_.base == BaseRandomization::Owen ? kOwenBaseName : kRotatedBaseName},
      {"mapping", settings_.mapped ? "mapped" : "unmapped"}};
  if (settings_.arch == NetworkArch::Graph) {
    m["neighbours"] = std::to_string(settings_.neighbours);
    m["rounds"] = std::to_string(settings_.rounds);
    m["position_harmonics"] = std::to_string(settings_.positionHarmonics);
    m["stages"] = std::to_string(settings_.stages);
    m["discrepancy_gradient"] = settings_.discrepancyGradient ? "1" : "0";
    // Only when on, so files from before keep their metadata.
    if (settings_.centred) m["centred"] = "1";
  }
  // Only for several sizes, so single-size files keep their metadata.
  if (!settings_.trainingNs.empty()) m["training_n"] = joinSizes(settings_.trainingNs);
  return m;
}

ModelFile NeuralGenerator::toModelFile(const std::map<std::string, std::string> &extra) const {
  ModelFile file;
  file.metadata = extra;
  for (const auto &[k, v] : metadata()) file.metadata[k] = v;
  file.tensors = network().tensors();
  return file;
}

void NeuralGenerator::save(const std::string &path,
                           const std::map<std::string, std::string> &extra) const {
  writeModelFile(path, toModelFile(extra));
}

void NeuralGenerator::loadWeights(const ModelFile &file, const std::string &path) {
  network().loadWeights(file, path);
}

NeuralGenerator NeuralGenerator::load(const std::string &path, NetworkLoad when) {
  ModelFile file = readModelFile(path);
  NeuralSettings s = NeuralSettings::fromModelFile(file, path);
  try {
    NeuralGenerator gen(std::move(s), NetworkLoad::OnFirstUse);
    gen.fileChecksum_ = file.checksum;
    gen.path_ = path;
    gen.pendingWeights_ = std::move(file);
    if (when == NetworkLoad::Now) gen.network();
    return gen;
  } catch (const std::invalid_argument &e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace nuld
