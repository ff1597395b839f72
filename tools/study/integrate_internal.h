#pragma once
// Helpers shared by the integration study's translation units (options,
// runner): kept out of integration_study.h, which is the public interface.

#include <string>
#include <vector>

namespace nuld::study {

// "a, b, c", for messages that list the accepted names.
std::string joinNames(const std::vector<std::string> &names);
// A CSV value with 12 significant digits (formatNumber gives 6).
std::string formatPrecise(double v);

}  // namespace nuld::study
