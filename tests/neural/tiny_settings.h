#pragma once
// Settings of a small generator for the neural tests: each suite fixes its
// own seed so that its expectations do not move when another suite's do.

#include <string>

#include "sampler/neural/neural_generator.h"
#include "sampler/neural/neural_trainer.h"

namespace nuld::test {

inline NeuralSettings tinyNeuralSettings(const std::string &family, std::size_t n, int hidden,
                                         bool mapped, std::uint64_t seed) {
  NeuralSettings s;
  s.mapped = mapped;
  s.n = n;
  s.hidden = hidden;
  s.family = family;
  s.seed = seed;
  return s;
}

// A few steps of small batches with few boxes and a gentle schedule.
inline TrainerSettings tinyTrainerSettings(int steps, std::uint64_t seed) {
  TrainerSettings t;
  t.steps = steps;
  t.batch = 4;
  t.boxes = 256;
  t.alphaStart = 10;
  t.alphaEnd = 200;
  t.lrStart = 3e-3;
  t.lrEnd = 1e-4;
  t.seed = seed;
  return t;
}

}  // namespace nuld::test
