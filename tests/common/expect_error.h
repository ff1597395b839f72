#pragma once
// The message of the exception a call throws: the tests of bad input check
// that the refusal names what was wrong, not only that it threw.

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace nuld::test {

// The what() of the exception of type E that `f` throws; records a failure
// and returns "" when it throws nothing.
template <class E = std::invalid_argument>
std::string errorMessage(const std::function<void()> &f) {
  try {
    f();
  } catch (const E &e) {
    return e.what();
  }
  ADD_FAILURE() << "the expected exception was not thrown";
  return "";
}

// Expects `f` to throw std::invalid_argument whose message mentions `what`.
inline void expectRefusalMentioning(const std::function<void()> &f, const std::string &what) {
  const std::string message = errorMessage(f);
  EXPECT_NE(message.find(what), std::string::npos)
      << "the refusal does not mention '" << what << "': " << message;
}

}  // namespace nuld::test
