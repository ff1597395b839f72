#include "backends/plugin_backend.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>

#include "plugins/nuld_sampler.h"
#include "sampler/io/round_trip.h"
#include "sampler/plugin.h"

namespace nuld {
namespace {

static_assert(sizeof(Point2) == 2 * sizeof(double), "fill writes Point2s as pairs of doubles");

// Version 1's interface (plugins/v1/nuld_sampler.h), as nuld still calls it:
// 2D pairs numbered camera 0, then per bounce d a light pair 1 + 3d, a BSDF
// pair 2 + 3d and a roulette pair 3 + 3d.
struct V1Setup {
  std::uint64_t seed;
  std::uint32_t spp, width, height, pairs;
  const char *arguments;
  std::uint32_t pairs_served;
  char error[256];
};
struct V1Sampler {
  void *(*create)(V1Setup *setup);
  int (*fill)(const void *state, std::uint32_t x, std::uint32_t y, std::uint32_t pair,
              std::uint32_t first, std::uint32_t count, double *xy);
  void (*destroy)(void *state);
};

// The version-1 pair that carries a domain, and the coordinate (-1: both):
// the 2D domains their own pairs, roulette the roulette pair's x and the
// light choice its y (where version 1 took them); the lobe choice none.
struct V1Pair {
  std::uint32_t pair;
  int coordinate;
};
std::optional<V1Pair> v1PairOf(std::uint32_t domain) {
  const SampleDomain d = SampleLayout::domain(domain);
  const std::uint32_t base = 3 * std::uint32_t(d.bounce);
  switch (d.role) {
    case SampleRole::Camera: return V1Pair{0, -1};
    case SampleRole::Light: return V1Pair{1 + base, -1};
    case SampleRole::Bsdf: return V1Pair{2 + base, -1};
    case SampleRole::Roulette: return V1Pair{3 + base, 0};
    case SampleRole::LightChoice: return V1Pair{3 + base, 1};
    case SampleRole::LobeChoice: return std::nullopt;
  }
  return std::nullopt;
}

const void *loadSampler(const std::string &path, int &version) {
  PluginSpec spec{"", "", "nuld_sampler_entry", NULD_SAMPLER_VERSION, "the sampler plugin"};
  spec.oldestVersion = 1;
  return loadPluginFile(path, spec,
                        "rebuild it against this nuld's plugins/nuld_sampler.h, version " +
                            std::to_string(NULD_SAMPLER_VERSION),
                        &version);
}

const nuld_sampler &v2(const void *plugin) { return *static_cast<const nuld_sampler *>(plugin); }
const V1Sampler &v1(const void *plugin) { return *static_cast<const V1Sampler *>(plugin); }

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
  plugin_ = loadSampler(path_, version_);
  const bool complete = version_ == 1
                            ? v1(plugin_).create && v1(plugin_).fill && v1(plugin_).destroy
                            : v2(plugin_).create && v2(plugin_).fill && v2(plugin_).destroy;
  if (!complete)
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

int PluginBackend::guardedFill(std::uint32_t x, std::uint32_t y, std::uint32_t domain,
                               std::span<double> out) const {
  std::fill(out.begin(), out.end(), std::numeric_limits<double>::quiet_NaN());
  inFlight_.fetch_add(1, std::memory_order_relaxed);
  int code;
  {
    const InsidePlugin inside;
    if (version_ == 1) {
      const std::uint32_t n = std::uint32_t(out.size() / 2);
      code = v1(plugin_).fill(state_, x, y, v1PairOf(domain)->pair, 0, n, out.data());
    } else {
      const nuld_domain &d = layout_[domain];
      code = v2(plugin_).fill(state_, x, y, &d, 0, std::uint32_t(out.size() / d.dimensions),
                              out.data());
    }
  }
  inFlight_.fetch_sub(1, std::memory_order_relaxed);
  returned_.fetch_add(1, std::memory_order_relaxed);
  return code;
}

std::size_t PluginBackend::numbersOf(std::uint32_t domain, std::size_t spp) const {
  return spp * (version_ == 1 ? 2 : std::size_t(SampleLayout::dimensions(domain)));
}

void PluginBackend::checkPurity(std::size_t spp, const SamplingTargets &targets) const {
  // Corners and the middle, the first and the last domain served.
  const std::uint32_t w = std::max<std::uint32_t>(1, targets.width),
                      h = std::max<std::uint32_t>(1, targets.height);
  std::uint32_t first = targets.domains, last = 0;
  for (std::uint32_t d = 0; d < targets.domains; ++d)
    if (rest_.serves(d)) first = std::min(first, d), last = d;
  if (first == targets.domains) return;
  struct Call {
    std::uint32_t x, y, domain;
  };
  const Call calls[] = {
      {0, 0, first}, {w - 1, h - 1, last}, {w / 2, h / 2, first}, {w / 2, h / 2, last}};
  const auto fillAll = [&] {
    std::vector<double> numbers;
    for (const Call &c : calls) {
      std::vector<double> one(numbersOf(c.domain, spp));
      if (guardedFill(c.x, c.y, c.domain, one) != 0)
        return std::vector<double>{};  // primary() reports the code
      numbers.insert(numbers.end(), one.begin(), one.end());
    }
    return numbers;
  };
  const std::vector<double> here = fillAll();
  std::vector<double> there;
  std::thread([&] { there = fillAll(); }).join();
  if (here.empty() || there.empty()) return;
  if (std::memcmp(here.data(), there.data(), here.size() * sizeof(double)) != 0)
    throw BackendRefusal("the sampler plugin " + path_ +
                         ": fill gave other numbers for the same pixel and domain when called "
                         "again from another thread; expected a pure function of its arguments "
                         "and the state create returned (plugins/README.md): a sampler that "
                         "keeps changing state makes every render differ");
}

PluginBackend::~PluginBackend() {
  if (state_) destroyState();
}

void PluginBackend::destroyState() {
  if (version_ == 1)
    v1(plugin_).destroy(state_);
  else
    v2(plugin_).destroy(state_);
  state_ = nullptr;
}

void PluginBackend::prepare(std::size_t spp, const SamplingTargets &targets) {
  if (state_) destroyState();
  std::vector<bool> served(targets.domains, true);
  std::string why;
  if (version_ == 1) {
    V1Setup setup{};
    setup.seed = seed_;
    setup.spp = std::uint32_t(spp);
    setup.width = targets.width, setup.height = targets.height;
    const std::uint32_t bounces =
        (std::max<std::uint32_t>(1, targets.domains) - 1) / SampleLayout::kPerBounce;
    setup.pairs = targets.domains == 0 ? 0 : 1 + 3 * bounces;
    setup.arguments = arguments_.c_str();
    setup.pairs_served = setup.pairs;
    {
      const InsidePlugin inside;
      state_ = v1(plugin_).create(&setup);
    }
    why.assign(setup.error, strnlen(setup.error, sizeof setup.error));
    for (std::uint32_t d = 0; d < targets.domains; ++d) {
      const auto pair = v1PairOf(d);
      served[d] = pair && pair->pair < setup.pairs_served;
    }
  } else {
    layout_.assign(targets.domains, {});
    for (std::uint32_t d = 0; d < targets.domains; ++d) {
      const SampleDomain sd = SampleLayout::domain(d);
      layout_[d] = {d,
                    std::uint32_t(sd.role),
                    std::uint32_t(sd.bounce),
                    std::uint32_t(sd.dimensions),
                    SampleLayout::firstDimension(d),
                    1};
    }
    nuld_sampler_setup setup{};
    setup.seed = seed_;
    setup.spp = std::uint32_t(spp);
    setup.width = targets.width, setup.height = targets.height;
    setup.integrator = targets.integrator.c_str();
    setup.domains = targets.domains;
    setup.layout = layout_.data();
    setup.arguments = arguments_.c_str();
    {
      const InsidePlugin inside;
      state_ = v2(plugin_).create(&setup);
    }
    why.assign(setup.error, strnlen(setup.error, sizeof setup.error));
    // What create said, kept apart from what fill is handed.
    for (std::uint32_t d = 0; d < targets.domains; ++d) {
      served[d] = layout_[d].served != 0;
      layout_[d] = {d,
                    std::uint32_t(SampleLayout::domain(d).role),
                    std::uint32_t(SampleLayout::bounceOf(d)),
                    std::uint32_t(SampleLayout::dimensions(d)),
                    SampleLayout::firstDimension(d),
                    served[d] ? 1u : 0u};
    }
  }
  if (!state_)
    throw BackendRefusal("the sampler plugin " + path_ + " refused the render (" +
                         std::to_string(spp) + " spp, " + std::to_string(targets.width) + "x" +
                         std::to_string(targets.height) +
                         "): " + (why.empty() ? "it gave no reason" : why));
  width_ = std::max<std::uint32_t>(1, targets.width);
  rest_.prepare("the plugin", std::move(served), spp, targets);
  checkPurity(spp, targets);
}

void PluginBackend::checkedFill(std::uint64_t pixel, std::uint32_t domain,
                                std::span<double> out) const {
  const auto x = std::uint32_t(pixel % width_), y = std::uint32_t(pixel / width_);
  const auto where = [&] {
    return " for pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), " +
           SobolRest::domainName(domain) +
           (version_ == 1 ? " (version 1's pair " + std::to_string(v1PairOf(domain)->pair) + ")"
                          : "");
  };
  if (const int code = guardedFill(x, y, domain, out))
    throw std::runtime_error("the sampler plugin " + path_ + ": fill returned " +
                             std::to_string(code) + where());
  const std::size_t dims = version_ == 1 ? 2 : std::size_t(SampleLayout::dimensions(domain));
  const std::size_t n = out.size() / dims;
  for (std::size_t i = 0; i < n; ++i) {
    const std::span<const double> sample = out.subspan(i * dims, dims);
    if (std::all_of(sample.begin(), sample.end(), [](double v) { return std::isnan(v); }))
      throw std::runtime_error(
          "the sampler plugin " + path_ + ": fill returned 0 but left sample " + std::to_string(i) +
          " of " + std::to_string(n) + " unwritten" + where() +
          " (nuld fills the buffer with NaN first); expected every sample written");
    if (!std::all_of(sample.begin(), sample.end(), [](double v) { return v >= 0 && v < 1; })) {
      std::string values;
      for (const double v : sample) values += (values.empty() ? "" : ", ") + formatRoundTrip(v);
      throw std::runtime_error("the sampler plugin " + path_ + " gave (" + values + ")" + where() +
                               ", sample " + std::to_string(i) + ": expected numbers in [0, 1)");
    }
  }
}

void PluginBackend::primary(std::uint64_t pixel, std::uint32_t domain,
                            std::span<Point2> out) const {
  if (!rest_.serves(domain) || !state_) return rest_.primary(pixel, domain, out);
  checkedFill(pixel, domain, {reinterpret_cast<double *>(out.data()), 2 * out.size()});
}

void PluginBackend::primary1D(std::uint64_t pixel, std::uint32_t domain,
                              std::span<double> out) const {
  if (!rest_.serves(domain) || !state_) return rest_.primary1D(pixel, domain, out);
  if (version_ != 1) return checkedFill(pixel, domain, out);
  // Version 1: the coordinate of the pair that carries it.
  thread_local std::vector<double> pair;
  pair.resize(2 * out.size());
  checkedFill(pixel, domain, pair);
  const int c = v1PairOf(domain)->coordinate;
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = pair[2 * i + std::size_t(c)];
}

}  // namespace nuld
