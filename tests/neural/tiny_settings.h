#pragma once
// Settings of a small generator for the neural tests: each suite fixes its
// own seed so that its expectations do not move when another suite's do.

#include <string>

#include "sampler/neural/neural_generator.h"

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

}  // namespace nuld::test
