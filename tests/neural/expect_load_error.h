#pragma once
// Loading a bad model file must fail with a message that names the file and
// says what is wrong (`fragment`).

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sampler/neural/neural_generator.h"

namespace nuld::test {

inline void expectLoadError(const std::string &path, const std::string &fragment) {
  try {
    NeuralGenerator::load(path);
    FAIL() << path;
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace nuld::test
