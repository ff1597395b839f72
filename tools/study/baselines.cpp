#include "tools/study/baselines.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "tools/study/csv_table.h"
#include "tools/study/render_study.h"

namespace nuld::study {

bool isClassicBackend(const std::string &word) {
  try {
    const BackendWord b = parseBackendWord(word);
    // A kind that takes no argument reads no sets and no model.
    return b.sets == BackendSets::None && b.spec.entry().argument.empty();
  } catch (const std::invalid_argument &) {
    return false;
  }
}

bool isPluginBackend(const std::string &word) {
  try {
    return parseBackendWord(word).spec.kind == BackendKind::Plugin;
  } catch (const std::invalid_argument &) {
    return false;
  }
}

std::vector<ClassicBaseline> classicBaselines(const std::vector<TimedRow> &rows) {
  std::vector<bool> classic;
  std::map<std::pair<std::string, std::size_t>, const TimedRow *> best;
  for (const TimedRow &r : rows) {
    classic.push_back(isClassicBackend(r.backend));
    if (!classic.back() || !std::isfinite(r.mse)) continue;
    const TimedRow *&b = best[{r.scene, r.spp}];
    if (!b || r.mse < b->mse) b = &r;
  }
  std::vector<ClassicBaseline> out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const TimedRow &r = rows[i];
    ClassicBaseline c;
    if (const auto it = best.find({r.scene, r.spp}); it != best.end()) {
      c.backend = it->second->backend;
      if (!classic[i]) {
        c.ratio = ratioOfMeans(r.mse, r.mseStderr, it->second->mse, it->second->mseStderr);
        if (!isPluginBackend(r.backend)) c.breakEven = breakEvenRenders(r, *it->second);
      }
    }
    out.push_back(c);
  }
  return out;
}

Ratio breakEvenRenders(const TimedRow &learned, const TimedRow &classic) {
  const double m = learned.mse, b = classic.mse;
  if (!(m > 0) || !(b > 0)) return {};
  // K (b T - m s) > m U - b V: the learned row's gain per render against
  // its extra setup.
  const double gain = b * classic.seconds - m * learned.seconds;
  const double extra = m * learned.setupSeconds - b * classic.setupSeconds;
  const double gainStderr =
      std::hypot(classic.seconds * classic.mseStderr, learned.seconds * learned.mseStderr);
  const double inf = std::numeric_limits<double>::infinity();
  if (!(gain > 0)) return {gain > extra ? 1.0 : inf, inf};
  const double crossing = extra / gain;
  const double k = crossing < 1 ? 1.0 : std::floor(crossing) + 1;
  if (gain < 2 * gainStderr) return {k, inf};
  // d crossing / d m and d / d b.
  const double dm = (learned.setupSeconds * gain + extra * learned.seconds) / (gain * gain),
               db = -(classic.setupSeconds * gain + extra * classic.seconds) / (gain * gain);
  return {k, std::hypot(dm * learned.mseStderr, db * classic.mseStderr)};
}

NoiseCorrected lessReferenceNoise(double mse, double relmse, const ReferenceNoise &noise) {
  NoiseCorrected c;
  c.mse = mse - noise.variance;
  c.relmse = relmse - noise.relVariance;
  c.tooNoisy = mse < kTooNoisyFactor * noise.variance;
  return c;
}

const std::vector<std::string> &baselineColumns() {
  static const std::vector<std::string> names{
      "mse_less_reference",    "relmse_less_reference",     "reference_too_noisy",
      "best_classic",          "mse_ratio_best_classic",    "mse_ratio_best_classic_stderr",
      "break_even_renders",    "break_even_renders_stderr", "mse_ratio_sobol",
      "mse_ratio_sobol_stderr"};
  return names;
}

const std::vector<std::string> &screenColumns() {
  static const std::vector<std::string> names{"screen_mse",
                                              "screen_mse_stderr",
                                              "screen_ratio_sobol",
                                              "screen_ratio_sobol_stderr",
                                              "best_classic_screen",
                                              "screen_ratio_best_classic",
                                              "screen_ratio_best_classic_stderr"};
  return names;
}

const std::vector<std::string> &flipColumns() {
  static const std::vector<std::string> names{"flip",
                                              "flip_stderr",
                                              "flip_ratio_sobol",
                                              "flip_ratio_sobol_stderr",
                                              "best_classic_flip",
                                              "flip_ratio_best_classic",
                                              "flip_ratio_best_classic_stderr"};
  return names;
}

const std::vector<std::string> &robustColumns() {
  static const std::vector<std::string> names{"mse_winsorized",
                                              "mse_winsorized_stderr",
                                              "top_share",
                                              "winsorized_ratio_best_classic",
                                              "winsorized_ratio_best_classic_stderr",
                                              "ruled_by_outliers",
                                              "stopped_on",
                                              "worst_relative_stderr"};
  return names;
}

namespace {

// The winsorized ratios and the outlier flag, against the best classic row
// by MSE (rows without a winsorized MSE, from an older file, get none).
void fillRobustRatios(CsvTable &table, const std::vector<TimedRow> &rows,
                      const std::vector<ClassicBaseline> &classic) {
  const std::size_t mean = table.column("mse_winsorized"),
                    stderr_ = table.column("mse_winsorized_stderr");
  std::map<std::pair<std::string, std::size_t>, std::size_t> best;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (!classic[i].backend.empty() && rows[i].backend == classic[i].backend)
      best[{rows[i].scene, rows[i].spp}] = i;
  std::vector<std::vector<std::string>> values(3);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    Ratio w, m;
    const auto it = best.find({rows[i].scene, rows[i].spp});
    if (it != best.end() && it->second != i) {
      const auto &r = table.rows()[i], &b = table.rows()[it->second];
      w = ratioOfMeans(parseNumber(r[mean]), parseNumber(r[stderr_]), parseNumber(b[mean]),
                       parseNumber(b[stderr_]));
      const TimedRow &br = rows[it->second];
      m = ratioOfMeans(rows[i].mse, rows[i].mseStderr, br.mse, br.mseStderr);
    }
    const Verdict vw = verdictOf(w.value, w.stderr_), vm = verdictOf(m.value, m.stderr_);
    const bool known = vw != Verdict::Undecided && vm != Verdict::Undecided;
    values[0].push_back(formatNumber(w.value));
    values[1].push_back(formatNumber(w.stderr_));
    values[2].push_back(!known ? "" : vw != vm ? "1" : "0");
  }
  for (std::size_t k = 0; k < values.size(); ++k)
    table.setColumn(robustColumns()[3 + k], values[k]);
}

// The ratio columns of a measured error (the screen error, FLIP: `columns`
// are its mean and standard error, then the five ratio columns), from each
// row's mean (rows without one, from an older file, get none).
void fillMetricRatios(CsvTable &table, const std::vector<std::string> &columns) {
  const std::size_t scene = table.column("scene"), backend = table.column("backend"),
                    spp = table.column("spp"), mean = table.column(columns[0]),
                    stderr_ = table.column(columns[1]);
  struct Metric {
    std::string backend;
    double mean = NAN, stderr_ = NAN;
  };
  std::map<std::pair<std::string, std::string>, Metric> sobol, best;
  std::vector<Metric> rows;
  for (const auto &r : table.rows()) {
    const Metric s{r[backend], parseNumber(r[mean]), parseNumber(r[stderr_])};
    rows.push_back(s);
    if (!std::isfinite(s.mean)) continue;
    const auto key = std::pair(r[scene], r[spp]);
    if (s.backend == "sobol") sobol[key] = s;
    if (!isClassicBackend(s.backend)) continue;
    if (const auto it = best.find(key); it == best.end() || s.mean < it->second.mean) best[key] = s;
  }
  std::vector<std::vector<std::string>> values(5);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto &r = table.rows()[i];
    const auto key = std::pair(r[scene], r[spp]);
    const auto ratioTo = [&](const std::map<std::pair<std::string, std::string>, Metric> &to) {
      const auto it = to.find(key);
      return it == to.end()
                 ? Ratio{}
                 : ratioOfMeans(rows[i].mean, rows[i].stderr_, it->second.mean, it->second.stderr_);
    };
    // sobol's own row is 1 exactly, as the table prints it.
    const Ratio toSobol = rows[i].backend == "sobol" && std::isfinite(rows[i].mean)
                              ? Ratio{1.0, 0.0}
                              : ratioTo(sobol),
                toBest = ratioTo(best);
    const auto b = best.find(key);
    values[0].push_back(formatNumber(toSobol.value));
    values[1].push_back(formatNumber(toSobol.stderr_));
    values[2].push_back(b == best.end() ? "" : b->second.backend);
    values[3].push_back(formatNumber(toBest.value));
    values[4].push_back(formatNumber(toBest.stderr_));
  }
  for (std::size_t k = 0; k < values.size(); ++k) table.setColumn(columns[2 + k], values[k]);
}

}  // namespace

void fillBaselineColumns(CsvTable &table, const std::map<std::string, ReferenceNoise> &noise) {
  fillMetricRatios(table, screenColumns());
  fillMetricRatios(table, flipColumns());
  const std::vector<TimedRow> rows = timedRows(table);
  const std::vector<ClassicBaseline> classic = classicBaselines(rows);
  const std::size_t relmseColumn = table.column("relmse");
  std::map<std::pair<std::string, std::size_t>, const TimedRow *> sobol;
  for (const TimedRow &r : rows)
    if (r.backend == "sobol" && std::isfinite(r.mse)) sobol[{r.scene, r.spp}] = &r;
  std::vector<std::vector<std::string>> values(baselineColumns().size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    NoiseCorrected c;
    if (const auto it = noise.find(rows[i].scene); it != noise.end())
      c = lessReferenceNoise(rows[i].mse, parseNumber(table.rows()[i][relmseColumn]), it->second);
    values[0].push_back(formatNumber(c.mse));
    values[1].push_back(formatNumber(c.relmse));
    values[2].push_back(c.tooNoisy ? "1" : "0");
    values[3].push_back(classic[i].backend);
    values[4].push_back(formatNumber(classic[i].ratio.value));
    values[5].push_back(formatNumber(classic[i].ratio.stderr_));
    values[6].push_back(formatNumber(classic[i].breakEven.value));
    values[7].push_back(formatNumber(classic[i].breakEven.stderr_));
    // The MSE over sobol's at the same scene and spp (1 on sobol's own row).
    Ratio toSobol;
    if (const auto it = sobol.find({rows[i].scene, rows[i].spp}); it != sobol.end())
      toSobol = it->second == &rows[i] ? Ratio{1.0, 0.0}
                                       : ratioOfMeans(rows[i].mse, rows[i].mseStderr,
                                                      it->second->mse, it->second->mseStderr);
    values[8].push_back(formatNumber(toSobol.value));
    values[9].push_back(formatNumber(toSobol.stderr_));
  }
  for (std::size_t k = 0; k < values.size(); ++k) table.setColumn(baselineColumns()[k], values[k]);
  fillRobustRatios(table, rows, classic);
}

}  // namespace nuld::study
