#include "sampler/io/round_trip.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace nuld {

char *formatRoundTrip(char *first, char *last, double v) {
  const auto [end, ec] = std::to_chars(first, last, v);
  if (ec != std::errc()) throw std::length_error("formatRoundTrip: buffer too small");
  return end;
}

std::string formatRoundTrip(double v) {
  char buf[32];
  return std::string(buf, formatRoundTrip(buf, buf + sizeof buf, v));
}

std::string formatShort(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string formatNumber(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace nuld
