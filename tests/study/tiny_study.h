#pragma once
// The render study's tests share one tiny configuration and readers of its
// table (render_study_test.cpp, render_study_cases_test.cpp).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "tools/study/csv_table.h"
#include "tools/study/render_study.h"

namespace nuld::study::test {

namespace fs = std::filesystem;

inline RenderStudySettings tinyStudy(const fs::path &out) {
  RenderStudySettings s;
  s.scenes = {"default"};
  s.backends = {"independent", "sobol", "halton", "optimized", "optimized-uniform"};
  s.spp = {4, 64};
  s.render.width = 48, s.render.height = 32;
  s.repeats = 8;
  s.render.integrator = IntegratorKind::Direct;
  s.reference.spp = 1024;
  s.reference.passSpp = 512;
  s.sets.instances = 4;
  s.sets.epochs = 50;
  s.out = out;
  s.sets.cacheDir = out / "cache";           // not the user's cache: each study makes its own sets
  s.referenceCacheDir = out / "references";  // and its own reference
  return s;
}

inline std::map<std::string, std::string> asMap(const std::vector<std::string> &columns,
                                                const std::vector<std::string> &row) {
  std::map<std::string, std::string> m;
  for (std::size_t i = 0; i < columns.size(); ++i) m[columns[i]] = row[i];
  return m;
}

inline CsvTable readTable(const fs::path &dir) {
  CsvTable t(dir / "render.csv", renderStudyColumns(), renderStudyDerivedColumns());
  t.loadExisting();
  return t;
}

}  // namespace nuld::study::test
