// NeuralSettings: their checks, and the settings a model file records. No
// LibTorch here, so that a model file's metadata can be checked (and fuzzed,
// tests/fuzz/README.md) without building a network.

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/model_metadata.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

// Before building the network a file's metadata describes: the file must
// hold at least the weights every such network has (the supplement's: three
// hidden x hidden layers and a last layer of hidden x 2N; the graph one's:
// three per round and a last layer of hidden x 2), so that a corrupt or
// hostile 'hidden' or 'n' cannot make it allocate gigabytes first.
void requireWeightsFor(const NeuralSettings &s, const ModelFile &file, const std::string &path) {
  const double h = s.hidden;
  const double least = s.arch == NetworkArch::Graph ? 3.0 * s.rounds * h * h + 2 * h
                                                    : 3.0 * h * h + 2.0 * double(s.n) * h;
  double held = 0;
  for (const ModelTensor &t : file.tensors) held += double(t.data.size());
  if (held < least)
    throw std::runtime_error(path + ": the network its metadata describes (hidden " +
                             std::to_string(s.hidden) + ", n " + std::to_string(s.n) +
                             ") has at least " + formatRoundTrip(least) +
                             " weights, the file holds " + formatRoundTrip(held));
}

}  // namespace

void NeuralSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("neural: " + what); };
  if (n < 1 || n > (std::size_t(1) << 20)) bad("n must be in [1, 2^20]");
  if (hidden < 1 || hidden > 16384) bad("hidden width must be in [1, 16384]");
  if (!(sigma > 0 && std::isfinite(sigma))) bad("sigma must be positive");
  if (encodingDims < 2 || encodingDims % 2 != 0) bad("the encoding size must be even and >= 2");
  if (zHarmonics < 0 || zHarmonics > 32) bad("z harmonics must be in [0, 32]");
  if (!(offsetRange > 0 && offsetRange <= 1)) bad("the offset range must be in (0, 1]");
  if (!trainingNs.empty()) {
    if (arch != NetworkArch::Graph)
      bad("several training sizes need the graph generator (the supplement's network emits a "
          "fixed N)");
    if (trainingNs.size() > 64) bad("at most 64 training sizes");
    for (const std::size_t m : trainingNs)
      if (m < 1 || m > (std::size_t(1) << 20)) bad("training sizes must be in [1, 2^20]");
    if (trainingNs.front() != n) bad("n must be the first training size");
  }
  if (arch == NetworkArch::Graph) {
    if (zHarmonics != 0) bad("z harmonics belong to the supplement's network, not the graph one");
    if (neighbours < 1 || neighbours > 64) bad("neighbours must be in [1, 64]");
    if (rounds < 0 || rounds > 16) bad("rounds must be in [0, 16]");
    if (positionHarmonics < 1 || positionHarmonics > 16)
      bad("position harmonics must be in [1, 16]");
    if (stages < 1 || stages > 16) bad("stages must be in [1, 16]");
    if (base == BaseRandomization::Owen && offsetRange != 1)
      bad("the offset range applies to the rotated base only");
  } else if (base != BaseRandomization::Rotated) {
    bad("the supplement's network needs the rotated base (its residuals are functions of z)");
  }
}

std::vector<std::size_t> NeuralSettings::sizesTrained() const {
  return trainingNs.empty() ? std::vector<std::size_t>{n} : trainingNs;
}

NeuralSettings NeuralSettings::fromModelFile(const ModelFile &file, const std::string &path) {
  if (file.metadata.count("format") == 0 || file.metadata.at("format") != kModelFormat)
    throw std::runtime_error(path + ": not a neural generator model (metadata 'format' is not '" +
                             kModelFormat + "')");
  if (file.value("version", path) != std::to_string(kModelVersion))
    throw std::runtime_error(path + ": model version " + file.value("version", path) +
                             ", this program reads version " + std::to_string(kModelVersion));
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
  // Whole numbers in [lo, hi]: the settings' own ranges are checked by
  // NeuralSettings::validate, this only keeps the conversion defined.
  auto integer = [&](const std::string &key, double lo, double hi) {
    const double x = number(key);
    if (!(x >= lo && x <= hi) || x != std::floor(x))
      throw std::runtime_error(path + ": model metadata '" + key + "' is " + file.value(key, path) +
                               ", expected a whole number from " + formatRoundTrip(lo) + " to " +
                               formatRoundTrip(hi));
    return x;
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
    s.neighbours = int(integer("neighbours", 0, 1 << 20));
    s.rounds = int(integer("rounds", 0, 1 << 20));
    s.positionHarmonics = int(integer("position_harmonics", 0, 1 << 20));
    s.stages = int(integer("stages", 0, 1 << 20));
    s.discrepancyGradient = integer("discrepancy_gradient", 0, 1) != 0;
    s.centred = file.metadata.count("centred") && integer("centred", 0, 1) != 0;
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
    if (base == kOwenBaseName)
      s.base = BaseRandomization::Owen;
    else if (base != kRotatedBaseName)
      throw std::runtime_error(path + ": model metadata 'base' is '" + base + "', expected '" +
                               kRotatedBaseName + "' or '" + kOwenBaseName + "'");
  }
  s.n = std::size_t(integer("n", 1, 1 << 30));
  s.hidden = int(integer("hidden", 1, 1 << 20));
  s.sigma = number("sigma");
  s.encodingDims = int(integer("encoding_dims", 0, 1 << 20));
  // Files from before these options have no keys: no harmonics, full range.
  if (file.metadata.count("z_harmonics")) s.zHarmonics = int(integer("z_harmonics", 0, 1 << 20));
  if (file.metadata.count("offset_range")) s.offsetRange = number("offset_range");
  {
    // from_chars: stoull would read "-1" as 2^64 - 1.
    const std::string &v = file.value("seed", path);
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), s.seed);
    if (ec != std::errc() || end != v.data() + v.size())
      throw std::runtime_error(path + ": model metadata 'seed' is '" + v +
                               "', expected a whole number from 0 to 2^64 - 1");
  }
  s.family = file.value("family", path);
  const std::string &mapping = file.value("mapping", path);
  if (mapping != "mapped" && mapping != "unmapped")
    throw std::runtime_error(path + ": model metadata 'mapping' is '" + mapping +
                             "', expected mapped or unmapped");
  s.mapped = mapping == "mapped";
  try {
    s.validate();
  } catch (const std::invalid_argument &e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  requireWeightsFor(s, file, path);
  return s;
}

}  // namespace nuld
