#pragma once
// The one round-trip number format: the shortest text that strtod,
// std::from_chars and istream >> read back as the same double ("0.1",
// "1e-07", "6000"). Point-set files, target specs, settings fingerprints and
// model metadata all write their numbers through it. formatShort is the
// other: three significant digits, for messages and headers a person reads;
// formatNumber, six, for the studies' CSV and progress lines.

#include <string>

namespace nuld {

std::string formatRoundTrip(double v);

// The same text written into [first, last), which has room for at least 32
// characters; returns the end of what was written.
char *formatRoundTrip(char *first, char *last, double v);

std::string formatShort(double v);  // "0.0123", "1e+04"

// %.6g, or "nan"/"inf" spelled as Python's csv/float() reads them.
std::string formatNumber(double v);

}  // namespace nuld
