#pragma once
// Where the neural generator's LibTorch code comes from: the networks and
// the trainer live in a plugin, libnuld_torch.so (sampler/plugin.h), that
// the first NeuralGenerator or NeuralTrainer loads, so that the processes
// that run no network (renders with classic backends, refused command
// lines, most tests) do not pay LibTorch's start-up.
//
// A binary that links the plugin's objects itself (the neural tests and
// benchmarks) uses them without loading anything.

#include <memory>
#include <span>

#include "sampler/point.h"

namespace nuld {

class NeuralGenerator;
class NeuralNet;
class NeuralTrainer;
struct TrainerSettings;

class NeuralRuntime {
 public:
  virtual ~NeuralRuntime() = default;
  // The network `generator` describes (its settings and family are set),
  // untrained; `sobol` is its rotated base set at offset 0.
  virtual std::unique_ptr<NeuralNet> makeNet(const NeuralGenerator &generator,
                                             std::span<const Point2> sobol) const = 0;
  virtual std::unique_ptr<NeuralTrainer> makeTrainer(NeuralGenerator &generator,
                                                     const TrainerSettings &settings) const = 0;
};

// Bumped whenever NeuralRuntime, NeuralNet, NeuralTrainer or the types they
// pass change, so that a plugin from another build is refused by name
// rather than called with the wrong layout.
inline constexpr int kNeuralRuntimeVersion = 1;

// The runtime: linked in, or the plugin's (loadPlugin; the variable is
// NULD_TORCH_PLUGIN). Throws std::runtime_error naming each place tried.
const NeuralRuntime &neuralRuntime();

}  // namespace nuld

// The plugin's one exported symbol: its runtime and the version it was built
// with. Weak here, so a binary that links the plugin's objects finds it
// without loading the plugin.
extern "C" const void *nuld_torch_runtime(int *version) __attribute__((weak));
