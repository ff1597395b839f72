#include "backends/plugin_backend.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "plugins/nuld_sampler.h"
#include "sampler/io/round_trip.h"
#include "sampler/plugin.h"

namespace nuld {
namespace {

static_assert(sizeof(Point2) == 2 * sizeof(double), "fill writes Point2s as pairs of doubles");

const nuld_sampler *loadSampler(const std::string &path) {
  const PluginSpec spec{"", "", "nuld_sampler_entry", NULD_SAMPLER_VERSION, "the sampler plugin"};
  return static_cast<const nuld_sampler *>(
      loadPluginFile(path, spec,
                     "rebuild it against this nuld's plugins/nuld_sampler.h, version " +
                         std::to_string(NULD_SAMPLER_VERSION)));
}

// "pair 5 (bounce 1's BSDF pair)": a pair as SamplePairs numbers it.
std::string pairName(std::uint32_t pair) {
  if (pair == SamplePairs::camera) return "pair 0 (the camera's)";
  const int depth = SamplePairs::depthOf(pair);
  const char *kind = pair == SamplePairs::light(depth)  ? "light"
                     : pair == SamplePairs::bsdf(depth) ? "BSDF"
                                                        : "roulette";
  return "pair " + std::to_string(pair) + " (bounce " + std::to_string(depth) + "'s " + kind + ")";
}

}  // namespace

PluginBackend::PluginBackend(std::string word, const std::string &argument, std::uint64_t seed)
    : word_(std::move(word)), seed_(seed), rest_(seed) {
  const auto colon = argument.find(':');
  path_ = argument.substr(0, colon);
  arguments_ = colon == std::string::npos ? "" : argument.substr(colon + 1);
  if (path_.empty())
    throw std::invalid_argument("backend '" + word_ + "': expected plugin:PATH[:ARGS]");
  plugin_ = loadSampler(path_);
  if (!plugin_->create || !plugin_->fill || !plugin_->destroy)
    throw std::runtime_error("the sampler plugin " + path_ +
                             ": its nuld_sampler lacks create, fill or destroy");
}

PluginBackend::~PluginBackend() {
  if (state_) plugin_->destroy(state_);
}

void PluginBackend::prepare(std::size_t spp, const SamplingTargets &targets) {
  if (state_) plugin_->destroy(state_), state_ = nullptr;
  nuld_sampler_setup setup{};
  setup.seed = seed_;
  setup.spp = std::uint32_t(spp);
  setup.width = targets.width, setup.height = targets.height;
  setup.pairs = targets.pairs;
  setup.arguments = arguments_.c_str();
  setup.pairs_served = targets.pairs;
  state_ = plugin_->create(&setup);
  if (!state_) {
    const std::string why(setup.error, strnlen(setup.error, sizeof setup.error));
    throw BackendRefusal("the sampler plugin " + path_ + " refused the render (" +
                         std::to_string(spp) + " spp, " + std::to_string(targets.width) + "x" +
                         std::to_string(targets.height) +
                         "): " + (why.empty() ? "it gave no reason" : why));
  }
  width_ = std::max<std::uint32_t>(1, targets.width);
  rest_.prepare("the plugin", setup.pairs_served, spp, targets);
}

void PluginBackend::primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const {
  if (pair >= rest_.served() || !state_) return rest_.primary(pixel, pair, out);
  const auto x = std::uint32_t(pixel % width_), y = std::uint32_t(pixel / width_);
  const auto where = [&] {
    return " for pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), " + pairName(pair);
  };
  if (const int code = plugin_->fill(state_, x, y, pair, 0, std::uint32_t(out.size()),
                                     reinterpret_cast<double *>(out.data())))
    throw std::runtime_error("the sampler plugin " + path_ + ": fill returned " +
                             std::to_string(code) + where());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Point2 p = out[i];
    if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1))
      throw std::runtime_error("the sampler plugin " + path_ + " gave the point (" +
                               formatRoundTrip(p.x) + ", " + formatRoundTrip(p.y) + ")" + where() +
                               ", sample " + std::to_string(i) + ": expected points in [0, 1)^2");
  }
}

}  // namespace nuld
