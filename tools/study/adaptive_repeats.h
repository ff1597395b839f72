#pragma once
// Repeats until the verdict is decided: which rows of a render study need
// more repeats for each of their MSE ratios (to the best classic row of
// their scene and spp, and to sobol's) to reach a target standard error,
// and how many, within a budget of repeats.
//
// The target is relative to the ratio: near 1, where verdicts are close,
// it is the ratio's standard error itself, and a row far from 1 is not
// rendered many times over only to pin down how far
// (tools/experiments/studies_that_tell.md, "Repeats until the verdict",
// measures both kinds of row). A ratio's relative error falls as
// 1 / sqrt(repeats) of both its rows (ratioOfMeans), so one of error e wants
// both rows' repeats times (e / target)^2; a round grows a row at least to
// double and at most to four times its repeats (the estimate from few
// repeats is itself noisy), never past the most. Repeat r is always
// rendered with seed + r, so the rows, and a rerun, come out the same
// whatever rounds added them.

#include <cstddef>
#include <string>
#include <vector>

#include "tools/study/equal_time.h"

namespace nuld::study {

struct RepeatBudget {
  double targetStderr = 0;      // relative, on each ratio; 0: fixed repeats
  std::size_t maxRepeats = 64;  // per row
  double seconds = 0;           // of the added repeats, per scene; 0: no limit
};

// Why a row's repeats stopped.
enum class RepeatStop {
  Fixed,      // no target: the repeats asked for
  Precision,  // every ratio of the row is within the target
  Budget,     // some ratio is not: the most repeats, or the seconds, ran out
};
const char *stopName(RepeatStop stop);  // "fixed", "precision", "budget"

struct RepeatPlan {
  // Per row, in order: the repeats it should have (its own when it needs no
  // more) and whether its ratios are within the target now.
  std::vector<std::size_t> want;
  std::vector<bool> decided;
  // The largest relative standard error of each row's ratios (0 when it
  // has none, infinity when one is unknown: a single repeat).
  std::vector<double> worstStderr;
};

// `repeats[i]` is row i's count. Rows of one scene and spp are compared
// with each other only.
RepeatPlan planRepeats(const std::vector<TimedRow> &rows, const std::vector<std::size_t> &repeats,
                       const RepeatBudget &budget);

}  // namespace nuld::study
