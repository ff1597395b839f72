#pragma once
// Error against run time: a render study's rows scored by MSE x seconds, the
// cost of reaching a given error (variance falls as 1/time for an unbiased
// estimator, so MSE x time is the constant a backend's line sits at).
//
// A row's time is its render seconds plus the setup its sets cost (optimizing
// them, building lobe tables), spread over the K renders the user expects to
// make with them (--amortize K): a set made once and used for K frames, or K
// views, costs 1/K of its setup per render. A set fetched from the cache
// costs nothing (setup 0).
//
// A row's render seconds are the median of its repeats, which a study
// renders interleaved across rows (every row's repeat 1, then every row's
// repeat 2, ...), so that work that comes and goes on the machine slows
// every row alike; their spread (seconds_mad) and the median's standard
// error (seconds_stderr, medianAndSpread in statistics.h) are kept beside
// them.
//
// equal_time_ratio is a row's MSE x total seconds over sobol's on the same
// scene and spp: below 1, the backend reaches sobol's error in less time.
// Its standard error counts both rows' MSE errors and their render times'
// (ratioOfMeans, statistics.h), so that a verdict needs the times decided as
// well as the errors; setup seconds are taken as exact.

#include <cstddef>
#include <string>
#include <vector>

#include "tools/study/statistics.h"

namespace nuld::study {

class CsvTable;

struct TimedRow {
  std::string scene, backend;
  std::size_t spp = 0;
  double mse = 0, mseStderr = 0;
  double seconds = 0, setupSeconds = 0;
  double secondsStderr = 0;  // the median render time's; 0 in a file from before it
};

struct EqualTime {
  double totalSeconds = 0;
  double ratio = 0, ratioStderr = 0;  // NaN when the scene and spp have no sobol row
};

// One result per row, in order. Throws std::invalid_argument unless amortize >= 1.
std::vector<EqualTime> equalTime(const std::vector<TimedRow> &rows, double amortize);

// Per (scene, spp), the backends with the lowest MSE x total seconds: the
// best, and every other whose product is within two standard errors of it
// (a tie). `separation` is the best's product over the runner-up's, with its
// standard error; a single backend has no runner-up (separation NaN).
struct TimeVerdict {
  std::string scene;
  std::size_t spp = 0;
  std::vector<std::string> best;  // best[0] has the lowest product; more: tied with it
  std::string runnerUp;           // the next backend beyond the tie ("" if none)
  double separation = 0, separationStderr = 0;
  EqualTime bestTime;  // best[0]'s
  // The best classic backend at the scene and spp (baselines.h) and, when
  // best[0] is learned, best[0]'s MSE over its (else NaN).
  std::string bestClassic;
  Ratio toBestClassic;
  Ratio breakEven;  // best[0]'s break-even renders against it (baselines.h), NaN if classic
};
std::vector<TimeVerdict> timeVerdicts(const std::vector<TimedRow> &rows, double amortize);

// The verdict as one line: "dragon, 64 spp: optimized-both, at 0.71+-0.02
// of sobol's MSE x time; ahead of sobol-tabulated at 0.83+-0.03 of its MSE x
// time; MSE 0.80+-0.03 of the best classic's (sobol-tabulated)".
std::string describe(const TimeVerdict &v);

// A render study table's rows as TimedRows (the columns of render.csv).
std::vector<TimedRow> timedRows(const CsvTable &table);

// render.csv's columns of the render times' spread: seconds_mad,
// seconds_stderr (missing from files written before them).
const std::vector<std::string> &timeSpreadColumns();

// The names of render.csv's columns that equalTime fills.
const std::vector<std::string> &equalTimeColumns();
// Fills them in every row of the table (rewriting its file), and writes the
// verdicts beside it (verdictColumns: scene, spp, best, tied
// (space-separated), runner_up, separation, separation_stderr,
// equal_time_ratio, equal_time_ratio_stderr, amortize, best_classic,
// mse_ratio_best_classic, mse_ratio_best_classic_stderr, break_even_renders,
// break_even_renders_stderr), which the study's page shows.
const std::vector<std::string> &verdictColumns();
void fillEqualTime(CsvTable &table, double amortize);

}  // namespace nuld::study
