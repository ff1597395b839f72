// The LibTorch plugin's door (neural_runtime.h): the one symbol it exports.

#include "sampler/neural/network.h"
#include "sampler/neural/neural_runtime.h"

namespace nuld {
namespace {

class TorchRuntime final : public NeuralRuntime {
 public:
  std::unique_ptr<NeuralNet> makeNet(const NeuralGenerator &generator,
                                     std::span<const Point2> sobol) const override {
    return makeTorchNet(generator, sobol);
  }
  std::unique_ptr<NeuralTrainer> makeTrainer(NeuralGenerator &generator,
                                             const TrainerSettings &settings) const override {
    return makeTorchTrainer(generator, settings);
  }
};

}  // namespace
}  // namespace nuld

extern "C" const void *nuld_torch_runtime(int *version) {
  static const nuld::TorchRuntime runtime;
  *version = nuld::kNeuralRuntimeVersion;
  return &runtime;
}
