#pragma once
// The message of the std::invalid_argument a call throws: the tests of bad
// input check that the refusal names what was wrong, not only that it threw.

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace nuld::test {

// The what() of the std::invalid_argument `f` throws; records a failure and
// returns "" when it throws nothing.
inline std::string invalidArgumentMessage(const std::function<void()> &f) {
  try {
    f();
  } catch (const std::invalid_argument &e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument was thrown";
  return "";
}

// Expects `f` to throw std::invalid_argument whose message mentions `what`.
inline void expectRefusalMentioning(const std::function<void()> &f, const std::string &what) {
  const std::string message = invalidArgumentMessage(f);
  EXPECT_NE(message.find(what), std::string::npos)
      << "the refusal does not mention '" << what << "': " << message;
}

}  // namespace nuld::test
