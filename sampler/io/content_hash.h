#pragma once
// FNV-1a, 64 bit: the project's stable hash for names, seeds and cache keys.
// Stable across runs, builds and machines (unlike std::hash), so a key made
// on one machine names the same entry on another. Not cryptographic: a key
// also carries the readable parts it was made from.

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

namespace nuld {

class ContentHash {
 public:
  ContentHash &add(std::string_view s) {
    for (unsigned char c : s) h_ = (h_ ^ c) * kPrime;
    return *this;
  }
  // Values by their bytes: the same doubles give the same hash on every
  // little-endian IEEE machine (all the project builds on).
  ContentHash &add(std::span<const double> v) {
    for (double x : v) add(x);
    return *this;
  }
  ContentHash &add(double x) {
    unsigned char b[sizeof x];
    std::memcpy(b, &x, sizeof x);
    return add(std::string_view(reinterpret_cast<const char *>(b), sizeof b));
  }
  ContentHash &add(std::uint64_t x) {
    unsigned char b[sizeof x];
    std::memcpy(b, &x, sizeof x);
    return add(std::string_view(reinterpret_cast<const char *>(b), sizeof b));
  }
  std::uint64_t value() const { return h_; }
  // 16 lower-case hex digits.
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h_));
    return out;
  }

 private:
  static constexpr std::uint64_t kPrime = 1099511628211ull;
  std::uint64_t h_ = 1469598103934665603ull;
};

inline std::uint64_t hashString(std::string_view s) { return ContentHash().add(s).value(); }

}  // namespace nuld
