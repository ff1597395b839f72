#pragma once
// The studies' suffix "+shift" on a sampler or backend word: its sets are
// then Cranley-Patterson shifted in the target's primary space per pixel or
// instance (as the renderer's shifted:PATHS, and as renders deal out a lobe
// model's sets). Parsed here for both studies' words.

#include <string>
#include <string_view>

namespace nuld::study {

struct ShiftSuffix {
  std::string base;  // the word without the suffix
  bool shifted = false;
};

inline ShiftSuffix splitShiftSuffix(const std::string &word) {
  constexpr std::string_view kShift = "+shift";
  if (word.size() > kShift.size() && word.ends_with(kShift))
    return {word.substr(0, word.size() - kShift.size()), true};
  return {word, false};
}

}  // namespace nuld::study
