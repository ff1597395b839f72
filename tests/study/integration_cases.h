#pragma once
// The integration study's tests share one quick configuration and readers
// of its table (integration_study_test.cpp, integration_study_words_test.cpp).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "tools/study/csv_table.h"
#include "tools/study/integration_study.h"

namespace nuld::study::test {

namespace fs = std::filesystem;

inline IntegrateOptions quickOptions(const fs::path &out) {
  IntegrateOptions o;
  o.outDir = out;
  o.cacheDir = out / "cache";  // not the user's cache: each test makes its own sets
  o.envmaps = {};
  o.instances = 16;
  o.optimizedInstances = 2;
  o.ns = {16, 64};
  return o;
}

inline CsvTable readCsv(const fs::path &dir) {
  CsvTable t(integrateCsvPath(dir), integrateColumns());
  t.loadExisting();
  return t;
}

// Row values by column name.
inline std::map<std::string, std::string> field(const CsvTable &t,
                                                const std::vector<std::string> &row) {
  std::map<std::string, std::string> m;
  for (std::size_t i = 0; i < t.columns().size(); ++i) m[t.columns()[i]] = row[i];
  return m;
}

inline const std::vector<std::string> *findRow(const CsvTable &t, const std::string &integrand,
                                               const std::string &sampler, std::size_t n) {
  for (const auto &r : t.rows())
    if (r[0] == integrand && r[2] == sampler && r[3] == std::to_string(n)) return &r;
  return nullptr;
}

inline double value(const CsvTable &t, const std::vector<std::string> &row,
                    const std::string &col) {
  return std::stod(field(t, row).at(col));
}

}  // namespace nuld::study::test
