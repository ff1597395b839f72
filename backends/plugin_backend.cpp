#include "backends/plugin_backend.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
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

// What the crash handler says: prepared before any signal (a handler may
// only call async-signal-safe functions), for the plugin loaded last.
char crashNote[1400];
// Whether this thread is inside a plugin's function now, so that a crash in
// nuld's own code is not blamed on the plugin.
thread_local volatile std::sig_atomic_t insidePlugin = 0;
constexpr int kCrashSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL};
struct sigaction previousAction[std::size(kCrashSignals)];

void onCrash(int signal) {
  if (insidePlugin) {
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, crashNote, std::strlen(crashNote));
  }
  // The previous action (the default: the process ends by the signal) runs
  // when the faulting instruction does again.
  for (std::size_t i = 0; i < std::size(kCrashSignals); ++i)
    if (kCrashSignals[i] == signal) sigaction(signal, &previousAction[i], nullptr);
}

void noteCrashesOf(const std::string &path) {
  std::snprintf(crashNote, sizeof crashNote,
                "\nnuld: the sampler plugin %s crashed inside its own code (create or fill); "
                "nuld cannot go on after a crash in a plugin: run it under a debugger "
                "(plugins/README.md, \"What nuld checks\")\n",
                path.c_str());
  static const bool installed = [] {
    for (std::size_t i = 0; i < std::size(kCrashSignals); ++i) {
      struct sigaction action {};
      action.sa_handler = onCrash;
      sigemptyset(&action.sa_mask);
      action.sa_flags = SA_NODEFER;
      sigaction(kCrashSignals[i], &action, &previousAction[i]);
    }
    return true;
  }();
  (void)installed;
}

// Marks this thread as inside the plugin for the crash note.
struct InsidePlugin {
  InsidePlugin() { insidePlugin = 1; }
  ~InsidePlugin() { insidePlugin = 0; }
};

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
  noteCrashesOf(path_);
  if (const char *stall = std::getenv("NULD_PLUGIN_STALL_SECONDS"); stall && *stall) {
    char *end = nullptr;
    stallSeconds_ = std::strtod(stall, &end);
    if (*end || !(stallSeconds_ > 0))
      throw std::invalid_argument("NULD_PLUGIN_STALL_SECONDS: '" + std::string(stall) +
                                  "' is not a positive number of seconds");
  }
  watchdog_ = std::jthread([this](std::stop_token stop) { watch(stop); });
}

void PluginBackend::watch(std::stop_token stop) {
  std::uint64_t seen = returned_.load();
  auto since = std::chrono::steady_clock::now();
  bool said = false;
  std::unique_lock lock(watchMutex_);
  while (!watchWake_.wait_for(lock, stop, std::chrono::milliseconds(250),
                              [&] { return stop.stop_requested(); })) {
    const auto now = std::chrono::steady_clock::now();
    const std::uint64_t returned = returned_.load(std::memory_order_relaxed);
    if (returned != seen || inFlight_.load(std::memory_order_relaxed) == 0) {
      seen = returned, since = now, said = false;
      continue;
    }
    if (!said && std::chrono::duration<double>(now - since).count() >= stallSeconds_) {
      std::cerr << "\nnuld: note: the sampler plugin " << path_
                << " has not returned from fill for " << stallSeconds_
                << " s; nuld waits for it (Ctrl-C ends the render)\n";
      said = true;
    }
  }
}

int PluginBackend::guardedFill(std::uint32_t x, std::uint32_t y, std::uint32_t pair,
                               std::span<Point2> out) const {
  std::fill(
      out.begin(), out.end(),
      Point2{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()});
  inFlight_.fetch_add(1, std::memory_order_relaxed);
  int code;
  {
    const InsidePlugin inside;
    code = plugin_->fill(state_, x, y, pair, 0, std::uint32_t(out.size()),
                         reinterpret_cast<double *>(out.data()));
  }
  inFlight_.fetch_sub(1, std::memory_order_relaxed);
  returned_.fetch_add(1, std::memory_order_relaxed);
  return code;
}

void PluginBackend::checkPurity(std::size_t spp, const SamplingTargets &targets) const {
  // Corners and the middle, the camera pair and the last pair served.
  const std::uint32_t w = std::max<std::uint32_t>(1, targets.width),
                      h = std::max<std::uint32_t>(1, targets.height);
  const std::uint32_t last = std::max<std::uint32_t>(1, rest_.served()) - 1;
  struct Call {
    std::uint32_t x, y, pair;
  };
  const Call calls[] = {{0, 0, 0}, {w - 1, h - 1, last}, {w / 2, h / 2, 0}, {w / 2, h / 2, last}};
  const auto fillAll = [&] {
    std::vector<Point2> points(std::size(calls) * spp);
    for (std::size_t i = 0; i < std::size(calls); ++i)
      if (guardedFill(calls[i].x, calls[i].y, calls[i].pair,
                      std::span<Point2>(points).subspan(i * spp, spp)) != 0)
        return std::vector<Point2>{};  // primary() reports the code
    return points;
  };
  const std::vector<Point2> here = fillAll();
  std::vector<Point2> there;
  std::thread([&] { there = fillAll(); }).join();
  if (here.empty() || there.empty()) return;
  if (std::memcmp(here.data(), there.data(), here.size() * sizeof(Point2)) != 0)
    throw BackendRefusal("the sampler plugin " + path_ +
                         ": fill gave other points for the same pixel and pair when called "
                         "again from another thread; expected a pure function of its arguments "
                         "and the state create returned (plugins/README.md): a sampler that "
                         "keeps changing state makes every render differ");
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
  {
    const InsidePlugin inside;
    state_ = plugin_->create(&setup);
  }
  if (!state_) {
    const std::string why(setup.error, strnlen(setup.error, sizeof setup.error));
    throw BackendRefusal("the sampler plugin " + path_ + " refused the render (" +
                         std::to_string(spp) + " spp, " + std::to_string(targets.width) + "x" +
                         std::to_string(targets.height) +
                         "): " + (why.empty() ? "it gave no reason" : why));
  }
  width_ = std::max<std::uint32_t>(1, targets.width);
  rest_.prepare("the plugin", setup.pairs_served, spp, targets);
  checkPurity(spp, targets);
}

void PluginBackend::primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const {
  if (pair >= rest_.served() || !state_) return rest_.primary(pixel, pair, out);
  const auto x = std::uint32_t(pixel % width_), y = std::uint32_t(pixel / width_);
  const auto where = [&] {
    return " for pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), " + pairName(pair);
  };
  if (const int code = guardedFill(x, y, pair, out))
    throw std::runtime_error("the sampler plugin " + path_ + ": fill returned " +
                             std::to_string(code) + where());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Point2 p = out[i];
    if (std::isnan(p.x) && std::isnan(p.y))
      throw std::runtime_error(
          "the sampler plugin " + path_ + ": fill returned 0 but left sample " + std::to_string(i) +
          " of " + std::to_string(out.size()) + " unwritten" + where() +
          " (nuld fills the buffer with NaN first); expected every point written");
    if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1))
      throw std::runtime_error("the sampler plugin " + path_ + " gave the point (" +
                               formatRoundTrip(p.x) + ", " + formatRoundTrip(p.y) + ")" + where() +
                               ", sample " + std::to_string(i) + ": expected points in [0, 1)^2");
  }
}

}  // namespace nuld
