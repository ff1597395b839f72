#pragma once
// plugin:PATH[:ARGS]: a user's sampler, compiled against the one C header
// plugins/nuld_sampler.h and loaded at run time (plugins/README.md). It
// serves primary points of the pairs it says it serves, every bounce's;
// the rest, and every lobe context, are sobol's, mapped classically.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stop_token>
#include <string>
#include <thread>

#include "backends/sobol_rest.h"
#include "renderer/sampler_backend.h"

struct nuld_sampler;

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
  // throws std::runtime_error naming the pixel, pair and sample.
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override;
  Report report() const override { return rest_.report(); }

 private:
  // fill() with the guards every call has: the crash note's marker, the
  // stall watchdog's counters, the NaN prefill.
  int guardedFill(std::uint32_t x, std::uint32_t y, std::uint32_t pair,
                  std::span<Point2> out) const;
  // Refuses a plugin whose fill is not a pure function of its arguments:
  // a few pixels' sets filled on this thread and again on another differ.
  void checkPurity(std::size_t spp, const SamplingTargets &targets) const;
  // Says on stderr, naming the plugin, when no fill has returned for
  // stallSeconds_ while one is in flight (a plugin in an endless loop).
  void watch(std::stop_token stop);

  std::string word_, path_, arguments_;
  std::uint64_t seed_;
  const nuld_sampler *plugin_;
  void *state_ = nullptr;  // the plugin's sampler for the prepared render
  std::uint32_t width_ = 1;
  SobolRest rest_;  // the pairs the plugin leaves
  mutable std::atomic<std::uint64_t> returned_{0};
  mutable std::atomic<int> inFlight_{0};
  double stallSeconds_ = 10;
  std::mutex watchMutex_;
  std::condition_variable_any watchWake_;
  std::jthread watchdog_;  // last: stopped and joined first
};

}  // namespace nuld
