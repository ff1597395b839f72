#pragma once
// What a render study's row is measured against, beyond Owen-Sobol:
//
// * the reference's own noise (reference_render.h, ReferenceNoise). Every
//   MSE against a reference of variance v is, in expectation, the row's own
//   error plus v, so a row reports its MSE less v too, and a row whose MSE
//   is below kTooNoisyFactor x v is flagged: there the comparison measures
//   the reference more than the row.
// * the strongest classic backend at the row's scene and spp (the study's
//   integrator is one for every row): the lowest mean MSE among the classic
//   rows present, those whose points come from a fixed construction rather
//   than from learned sets (isClassicBackend). A learned backend is worth
//   its setup only where it beats that, not merely sobol. Picking the lowest
//   of several noisy means favours the classic side a little: the
//   comparison errs against the learned row.
//
// Both fill columns of render.csv (baselineColumns), recomputed over the
// whole table after every row, as the equal-time columns are.

#include <map>
#include <string>
#include <vector>

#include "backends/reference_render.h"
#include "tools/study/equal_time.h"
#include "tools/study/statistics.h"

namespace nuld::study {

class CsvTable;

// A row whose MSE is below this many times the reference's variance is
// flagged "reference too noisy for this row".
inline constexpr double kTooNoisyFactor = 10;

// Whether a study backend word makes no learned sets: a renderer backend
// whose registry entry takes no argument (no point-set files, no model:
// independent, sobol, halton, sobol-tabulated and any such kind added to
// backends/backend_registry.h). The study's own sets (optimized*), banks
// (optimized:, shifted:) and models (neural) are learned. A word that no
// longer parses counts as learned.
bool isClassicBackend(const std::string &word);
// Whether a study backend word is a user's sampler plugin (plugin:PATH):
// it makes no sets and has no setup, so it is classed with the classic
// rows, but scored against the best built-in classic row, which it is not
// part of (docs/studies.md, "How rows are classed").
bool isPluginBackend(const std::string &word);

// Per row: the best classic backend at its scene and spp ("" when there is
// none) and, for a learned or plugin row, its MSE over that backend's, and
// for a learned row the renders after which it has paid for its setup
// (breakEvenRenders); NaN for a built-in classic row, a plugin's break-even
// (no setup), and when there is none.
struct ClassicBaseline {
  std::string backend;
  Ratio ratio;
  Ratio breakEven;  // breakEvenRenders, with its standard error
};

// The smallest number of renders K >= 1 for which the learned row reaches
// the classic row's error sooner: MSE x (seconds + setup / K) below the
// classic row's MSE x (seconds + setup / K) (each pays its own setup, a
// table's too). Infinity where no K does (the learned row is not ahead per
// render). The standard error is that of the real-valued K at which the two
// cross, from the two MSEs' (delta method; the times are taken as exact),
// infinite where the crossing is within two of them of never happening.
Ratio breakEvenRenders(const TimedRow &learned, const TimedRow &classic);
std::vector<ClassicBaseline> classicBaselines(const std::vector<TimedRow> &rows);

// Per row: MSE and relMSE less the reference's noise, and the flag.
struct NoiseCorrected {
  double mse = NAN, relmse = NAN;
  bool tooNoisy = false;
};
NoiseCorrected lessReferenceNoise(double mse, double relmse, const ReferenceNoise &noise);

// The screen-space error (renderer/image_metrics.h, ImageError::screen):
// each row's mean over its repeats with its standard error (measured), then
// its ratio to sobol's, the classic row with the lowest screen error at the
// row's scene and spp, and the ratio to that one's, for every row (a
// classic row's ratio says how far it is from the best). A file written
// before these existed lacks them all.
const std::vector<std::string> &screenColumns();

// The robust statistic and the repeats' stop: each row's MSE with its
// images' largest pixel errors winsorized (renderer/image_metrics.h,
// ImageError::winsorized: mean and standard error over the repeats,
// measured), the mean share of the squared error in those pixels
// (top_share), its ratio to the best classic row's (the row with the lowest
// MSE, as mse_ratio_best_classic; filled for every other row), and
// ruled_by_outliers: 1 where that ratio and the MSE's disagree (one better
// or worse by two standard errors, the other not, or the other way), so a
// few pixels decide the MSE's verdict. stopped_on (fixed, precision,
// budget) and worst_relative_stderr say why the row's repeats ended
// (adaptive_repeats.h). A file written before these existed lacks them all.
const std::vector<std::string> &robustColumns();

// HDR-FLIP (renderer/flip.h) as the screen error is: each row's mean over
// its repeats with its standard error (measured), its ratio to sobol's,
// the classic row with the lowest FLIP and the ratio to that one's.
const std::vector<std::string> &flipColumns();

// The names of render.csv's columns that fillBaselineColumns fills, beside
// the screen columns' ratios (all of screenColumns but the first two).
const std::vector<std::string> &baselineColumns();
// Fills them in every row of the table (rewriting its file), from the
// rows themselves and each scene's reference noise (a scene missing from
// `noise` gets NaN and no flag).
void fillBaselineColumns(CsvTable &table, const std::map<std::string, ReferenceNoise> &noise);

}  // namespace nuld::study
