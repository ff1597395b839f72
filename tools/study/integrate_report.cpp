// What `nuld study integrate` reports from its CSV: the plots and HTML page
// (drawn by report.py) and the RMSE table printed on the terminal.

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "tools/study/integration_study.h"
#include "tools/study/report_script.h"

namespace nuld::study {
namespace fs = std::filesystem;

std::optional<std::string> runIntegratePlots(const fs::path &outDir) {
  std::string why;
  // report.py draws plot_integrate.py's plots and the HTML page with them.
  const int status = runStudyScript("report.py", outDir, &why);
  if (status == 0) return std::nullopt;
  if (status < 0) return why + "; no plots made (the CSV is complete)";
  return "report.py exited with status " + std::to_string(status) +
         " (is python3-matplotlib installed?); the CSV is complete";
}

std::string rmseTable(const CsvTable &table) {
  const auto col = [&](const std::string &name) { return table.column(name); };
  const std::size_t ci = col("integrand"), cs = col("sampler"), cn = col("n"), cr = col("rmse"),
                    cref = col("reference");
  std::vector<std::string> integrands;
  for (const auto &r : table.rows())
    if (std::find(integrands.begin(), integrands.end(), r[ci]) == integrands.end())
      integrands.push_back(r[ci]);
  std::ostringstream out;
  for (const auto &name : integrands) {
    std::vector<std::string> samplers;
    std::set<std::size_t> ns;
    std::map<std::pair<std::string, std::size_t>, std::string> cell;
    std::string reference;
    for (const auto &r : table.rows()) {
      if (r[ci] != name) continue;
      if (std::find(samplers.begin(), samplers.end(), r[cs]) == samplers.end())
        samplers.push_back(r[cs]);
      const std::size_t n = std::stoul(r[cn]);
      ns.insert(n);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.3g", std::stod(r[cr]));
      cell[{r[cs], n}] = buf;
      reference = r[cref];
    }
    std::size_t width = 8;
    for (const auto &s : samplers) width = std::max(width, s.size() + 1);
    out << name << "  (RMSE; reference " << reference << ")\n";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%-*s", int(width), "sampler");
    out << buf;
    for (std::size_t n : ns) {
      std::snprintf(buf, sizeof buf, " %9s", ("N=" + std::to_string(n)).c_str());
      out << buf;
    }
    out << "\n";
    for (const auto &s : samplers) {
      std::snprintf(buf, sizeof buf, "%-*s", int(width), s.c_str());
      out << buf;
      for (std::size_t n : ns) {
        const auto it = cell.find({s, n});
        std::snprintf(buf, sizeof buf, " %9s", it == cell.end() ? "-" : it->second.c_str());
        out << buf;
      }
      out << "\n";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace nuld::study
