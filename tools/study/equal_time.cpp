#include "tools/study/equal_time.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "backends/ready_backend.h"
#include "tools/study/baselines.h"
#include "tools/study/csv_table.h"

namespace nuld::study {

namespace {

double product(const TimedRow &r, double amortize) {
  return r.mse * (r.seconds + r.setupSeconds / amortize);
}

// A row's product with its standard error: the relative errors of its MSE
// and of its total time (the render seconds', setup exact) in quadrature.
std::pair<double, double> productAndError(const TimedRow &r, double amortize) {
  const double t = r.seconds + r.setupSeconds / amortize;
  const double rm = relativeError(r.mseStderr, r.mse), rt = relativeError(r.secondsStderr, t);
  const double p = r.mse * t;
  return {p, p * std::sqrt(rm * rm + rt * rt)};
}

// The ratio a / b of two rows' products, with its standard error.
std::pair<double, double> ratioOf(const TimedRow &a, const TimedRow &b, double amortize) {
  const auto [pa, ea] = productAndError(a, amortize);
  const auto [pb, eb] = productAndError(b, amortize);
  const Ratio q = ratioOfMeans(pa, ea, pb, eb);
  return {q.value, q.stderr_};
}

}  // namespace

std::vector<EqualTime> equalTime(const std::vector<TimedRow> &rows, double amortize) {
  if (!(amortize >= 1) || !std::isfinite(amortize))
    throw std::invalid_argument("--amortize: expected a number of renders >= 1");
  std::map<std::pair<std::string, std::size_t>, const TimedRow *> sobol;
  for (const TimedRow &r : rows)
    if (r.backend == "sobol") sobol[{r.scene, r.spp}] = &r;
  std::vector<EqualTime> out;
  out.reserve(rows.size());
  for (const TimedRow &r : rows) {
    EqualTime e;
    e.totalSeconds = r.seconds + r.setupSeconds / amortize;
    e.ratio = e.ratioStderr = NAN;
    if (const auto it = sobol.find({r.scene, r.spp});
        it != sobol.end() && product(*it->second, amortize) > 0) {
      // sobol's own row is 1 exactly, not 1 with its error counted twice.
      if (&r == it->second)
        e.ratio = 1, e.ratioStderr = 0;
      else
        std::tie(e.ratio, e.ratioStderr) = ratioOf(r, *it->second, amortize);
    }
    out.push_back(e);
  }
  return out;
}

std::vector<TimeVerdict> timeVerdicts(const std::vector<TimedRow> &rows, double amortize) {
  const std::vector<EqualTime> times = equalTime(rows, amortize);
  const std::vector<ClassicBaseline> classic = classicBaselines(rows);
  // Groups in the order the rows first name them.
  std::vector<std::pair<std::string, std::size_t>> order;
  std::map<std::pair<std::string, std::size_t>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::pair key{rows[i].scene, rows[i].spp};
    if (!groups.contains(key)) order.push_back(key);
    if (std::isfinite(product(rows[i], amortize))) groups[key].push_back(i);
  }
  std::vector<TimeVerdict> out;
  for (const auto &key : order) {
    std::vector<std::size_t> g = groups[key];
    if (g.empty()) continue;
    std::stable_sort(g.begin(), g.end(), [&](std::size_t a, std::size_t b) {
      return product(rows[a], amortize) < product(rows[b], amortize);
    });
    TimeVerdict v;
    v.scene = key.first;
    v.spp = key.second;
    v.bestTime = times[g[0]];
    v.bestClassic = classic[g[0]].backend;
    v.toBestClassic = classic[g[0]].ratio;
    v.breakEven = classic[g[0]].breakEven;
    v.separation = v.separationStderr = NAN;
    const TimedRow &best = rows[g[0]];
    v.best.push_back(best.backend);
    for (std::size_t k = 1; k < g.size(); ++k) {
      const auto [q, se] = ratioOf(best, rows[g[k]], amortize);
      if (verdictOf(q, se) == Verdict::Better) {  // separated: the first one beyond the tie
        v.runnerUp = rows[g[k]].backend;
        v.separation = q;
        v.separationStderr = se;
        break;
      }
      v.best.push_back(rows[g[k]].backend);
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::string describe(const TimeVerdict &v) {
  char buf[160];
  std::string s = v.scene + ", " + std::to_string(v.spp) + " spp: ";
  if (v.best.size() == 1) {
    s += rowLabel(v.best[0]);
  } else {
    s += "tie between";
    for (std::size_t i = 0; i < v.best.size(); ++i)
      s += (i == 0 ? " " : i + 1 == v.best.size() ? " and " : ", ") + rowLabel(v.best[i]);
    s += " (within 2 standard errors; " + rowLabel(v.best[0]) + " lowest)";
  }
  if (std::isfinite(v.bestTime.ratio) && v.bestTime.ratioStderr > 0) {
    std::snprintf(buf, sizeof buf, ", at %.3f+-%.3f of sobol's MSE x time", v.bestTime.ratio,
                  v.bestTime.ratioStderr);
    s += buf;
  }
  if (!v.runnerUp.empty()) {
    std::snprintf(buf, sizeof buf, " at %.3f+-%.3f of its MSE x time", v.separation,
                  v.separationStderr);
    s += "; ahead of " + rowLabel(v.runnerUp) + buf;
  }
  if (std::isfinite(v.toBestClassic.value)) {
    std::snprintf(buf, sizeof buf, "; MSE %.3f+-%.3f of the best classic's", v.toBestClassic.value,
                  v.toBestClassic.stderr_);
    s += buf + (" (" + rowLabel(v.bestClassic) + ")");
  }
  return s;
}

std::vector<TimedRow> timedRows(const CsvTable &table) {
  const std::size_t scene = table.column("scene"), backend = table.column("backend"),
                    spp = table.column("spp"), mse = table.column("mse"),
                    mseErr = table.column("mse_stderr"), secs = table.column("seconds"),
                    setup = table.column("setup_seconds"),
                    secsErr = table.column(timeSpreadColumns()[1]);
  std::vector<TimedRow> out;
  for (const auto &r : table.rows()) {
    const double timeError = parseNumber(r[secsErr]);
    out.push_back({r[scene], r[backend], std::size_t(parseNumber(r[spp])), parseNumber(r[mse]),
                   parseNumber(r[mseErr]), parseNumber(r[secs]), parseNumber(r[setup]),
                   std::isfinite(timeError) ? timeError : 0.0});
  }
  return out;
}

const std::vector<std::string> &timeSpreadColumns() {
  static const std::vector<std::string> names{"seconds_mad", "seconds_stderr"};
  return names;
}

const std::vector<std::string> &equalTimeColumns() {
  static const std::vector<std::string> names{"total_seconds", "equal_time_ratio",
                                              "equal_time_ratio_stderr", "amortize"};
  return names;
}

const std::vector<std::string> &verdictColumns() {
  static const std::vector<std::string> names{"scene",
                                              "spp",
                                              "best",
                                              "tied",
                                              "runner_up",
                                              "separation",
                                              "separation_stderr",
                                              "equal_time_ratio",
                                              "equal_time_ratio_stderr",
                                              "amortize",
                                              "best_classic",
                                              "mse_ratio_best_classic",
                                              "mse_ratio_best_classic_stderr",
                                              "break_even_renders",
                                              "break_even_renders_stderr"};
  return names;
}

void fillEqualTime(CsvTable &table, double amortize) {
  const std::vector<EqualTime> times = equalTime(timedRows(table), amortize);
  std::vector<std::string> total, ratio, stderr_, k;
  for (const EqualTime &e : times) {
    total.push_back(formatNumber(e.totalSeconds));
    ratio.push_back(formatNumber(e.ratio));
    stderr_.push_back(formatNumber(e.ratioStderr));
    k.push_back(formatNumber(amortize));
  }
  const auto &names = equalTimeColumns();
  table.setColumn(names[0], total);
  table.setColumn(names[1], ratio);
  table.setColumn(names[2], stderr_);
  table.setColumn(names[3], k);

  CsvTable verdicts(table.path().parent_path() / "verdicts.csv", verdictColumns());
  for (const TimeVerdict &v : timeVerdicts(timedRows(table), amortize)) {
    std::string tied;
    for (std::size_t i = 1; i < v.best.size(); ++i) tied += (i > 1 ? " " : "") + v.best[i];
    verdicts.addRow({v.scene, std::to_string(v.spp), v.best[0], tied, v.runnerUp,
                     formatNumber(v.separation), formatNumber(v.separationStderr),
                     formatNumber(v.bestTime.ratio), formatNumber(v.bestTime.ratioStderr),
                     formatNumber(amortize), v.bestClassic, formatNumber(v.toBestClassic.value),
                     formatNumber(v.toBestClassic.stderr_), formatNumber(v.breakEven.value),
                     formatNumber(v.breakEven.stderr_)});
  }
}

}  // namespace nuld::study
