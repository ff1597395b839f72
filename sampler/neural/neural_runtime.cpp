#include "sampler/neural/neural_runtime.h"

#include "sampler/neural/neural_trainer.h"
#include "sampler/plugin.h"

namespace nuld {

const NeuralRuntime &neuralRuntime() {
  if (nuld_torch_runtime) {  // linked in
    int version = 0;
    return *static_cast<const NeuralRuntime *>(nuld_torch_runtime(&version));
  }
  return *static_cast<const NeuralRuntime *>(
      loadPlugin({"libnuld_torch.so", "NULD_TORCH_PLUGIN", "nuld_torch_runtime",
                  kNeuralRuntimeVersion, "the neural generator"}));
}

std::unique_ptr<NeuralTrainer> NeuralTrainer::make(NeuralGenerator &generator,
                                                   const TrainerSettings &settings) {
  return neuralRuntime().makeTrainer(generator, settings);
}

}  // namespace nuld
