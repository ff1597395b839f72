#pragma once
// plugin:PATH[:ARGS]: a user's sampler, compiled against the one C header
// plugins/nuld_sampler.h and loaded at run time (plugins/README.md). It
// serves primary samples of the domains it says it serves, every bounce's;
// the rest, and every lobe context, are sobol's, mapped classically. A
// version-1 plugin (2D pairs only) serves the 2D domains and the 1D ones its
// pairs used to carry, as plugins/README.md maps them.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "backends/sobol_rest.h"
#include "renderer/sampler_backend.h"

struct nuld_sampler;
struct nuld_domain;

namespace nuld {

class PluginBackend final : public SamplerBackend {
 public:
  // `argument`: PATH or PATH:ARGS. Loads the plugin (throwing
  // std::runtime_error naming the file and what is wrong with it).
  PluginBackend(std::string word, const std::string &argument, std::uint64_t seed);
  ~PluginBackend() override;
  PluginBackend(const PluginBackend &) = delete;
  PluginBackend &operator=(const PluginBackend &) = delete;

  std::string name() const override { return word_; }
  // Creates the plugin's sampler for this render; a plugin that refuses it
  // gives a BackendRefusal with its reason.
  void prepare(std::size_t spp, const SamplingTargets &targets) override;
  // The plugin's points, checked: a failed fill, a NaN, a point outside
  // [0, 1)^2 or one fill left unwritten (the buffer is prefilled with NaN)
  // throws std::runtime_error naming the pixel, domain and sample.
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override;
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override;
  Report report() const override { return rest_.report(); }

 private:
  // fill() of the domain's samples into out (N times its dimensions
  // numbers; a version-1 plugin: the numbers of the pair carrying it) with
  // the guards every call has: the crash note's marker, the stall
  // watchdog's counters, the NaN prefill.
  int guardedFill(std::uint32_t x, std::uint32_t y, std::uint32_t domain,
                  std::span<double> out) const;
  // How many numbers guardedFill writes for N = spp samples of the domain.
  std::size_t numbersOf(std::uint32_t domain, std::size_t spp) const;
  void destroyState();
  // The samples of (pixel, domain), checked, into out (N * dimensions).
  void checkedFill(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const;
  // Refuses a plugin whose fill is not a pure function of its arguments:
  // a few pixels' sets filled on this thread and again on another differ.
  void checkPurity(std::size_t spp, const SamplingTargets &targets) const;
  // Says on stderr, naming the plugin, when no fill has returned for
  // stallSeconds_ while one is in flight (a plugin in an endless loop).
  void watch(std::stop_token stop);

  std::string word_, path_, arguments_;
  std::uint64_t seed_;
  const void *plugin_;  // a nuld_sampler of version_
  int version_ = 0;
  void *state_ = nullptr;  // the plugin's sampler for the prepared render
  std::uint32_t width_ = 1;
  std::vector<nuld_domain> layout_;  // version 2: the layout create saw
  SobolRest rest_;                   // the domains the plugin leaves
  mutable std::atomic<std::uint64_t> returned_{0};
  mutable std::atomic<int> inFlight_{0};
  double stallSeconds_ = 10;
  std::mutex watchMutex_;
  std::condition_variable_any watchWake_;
  std::jthread watchdog_;  // last: stopped and joined first
};

}  // namespace nuld
