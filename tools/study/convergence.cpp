#include "tools/study/convergence.h"

#include <algorithm>
#include <map>
#include <set>

namespace nuld::study {

Ratio convergenceSlope(std::span<const double> spp, std::span<const double> error,
                       std::span<const double> stderr_) {
  const std::size_t n = spp.size();
  if (n < 3 || error.size() != n || stderr_.size() != n) return {};
  std::vector<double> x(n), y(n), w(n);
  bool weighted = true;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(spp[i] > 0) || !(error[i] > 0) || !std::isfinite(error[i])) return {};
    x[i] = std::log(spp[i]);
    y[i] = std::log(error[i]);
    const double relative = stderr_[i] / error[i];
    weighted = weighted && relative > 0 && std::isfinite(relative);
    w[i] = weighted ? 1 / (relative * relative) : 1;
  }
  if (!weighted) std::fill(w.begin(), w.end(), 1.0);
  double sw = 0, sx = 0, sy = 0;
  for (std::size_t i = 0; i < n; ++i) sw += w[i], sx += w[i] * x[i], sy += w[i] * y[i];
  const double mx = sx / sw, my = sy / sw;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i)
    sxx += w[i] * (x[i] - mx) * (x[i] - mx), sxy += w[i] * (x[i] - mx) * (y[i] - my);
  if (!(sxx > 0)) return {};
  const double slope = sxy / sxx;
  if (weighted) return {slope, std::sqrt(1 / sxx)};
  // Unweighted: the residuals' variance over n - 2 degrees of freedom.
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - my - slope * (x[i] - mx);
    rss += r * r;
  }
  return {slope, rss > 0 ? std::sqrt(rss / double(n - 2) / sxx) : NAN};
}

const std::vector<std::string> &slopeColumns() {
  static const std::vector<std::string> names{"scene",
                                              "backend",
                                              "spps",
                                              "mse_slope",
                                              "mse_slope_stderr",
                                              "screen_slope",
                                              "screen_slope_stderr"};
  return names;
}

std::vector<std::vector<std::string>> slopeRows(const CsvTable &table) {
  const std::size_t scene = table.column("scene"), backend = table.column("backend"),
                    spp = table.column("spp"), mse = table.column("mse"),
                    mseStderr = table.column("mse_stderr"), screen = table.column("screen_mse"),
                    screenStderr = table.column("screen_mse_stderr");
  // Rows by (scene, backend), in the table's order, sorted by spp.
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<const std::vector<std::string> *>>
      groups;
  for (const auto &r : table.rows()) {
    const auto key = std::pair(r[scene], r[backend]);
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  std::vector<std::vector<std::string>> out;
  for (const auto &key : order) {
    auto rows = groups[key];
    std::sort(rows.begin(), rows.end(), [&](const auto *a, const auto *b) {
      return parseNumber((*a)[spp]) < parseNumber((*b)[spp]);
    });
    std::set<double> distinct;
    for (const auto *r : rows) distinct.insert(parseNumber((*r)[spp]));
    if (distinct.size() < 3) continue;
    std::vector<double> n, m, me, s, se;
    std::string spps;
    for (const auto *r : rows) {
      n.push_back(parseNumber((*r)[spp]));
      m.push_back(parseNumber((*r)[mse]));
      me.push_back(parseNumber((*r)[mseStderr]));
      s.push_back(parseNumber((*r)[screen]));
      se.push_back(parseNumber((*r)[screenStderr]));
      spps += (spps.empty() ? "" : " ") + (*r)[spp];
    }
    const Ratio a = convergenceSlope(n, m, me), b = convergenceSlope(n, s, se);
    out.push_back({key.first, key.second, spps, formatNumber(a.value), formatNumber(a.stderr_),
                   formatNumber(b.value), formatNumber(b.stderr_)});
  }
  return out;
}

}  // namespace nuld::study
