#pragma once
// Convergence rates (docs/studies.md, "Convergence rates"): per scene and
// backend of a render study with three or more spp values, the slope of
// log error over log spp, the rate QMC papers report (-1 for Monte Carlo's
// MSE, steeper where a sampler's stratification pays), for the MSE and the
// screen error, with standard errors from the repeats.

#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "tools/study/csv_table.h"
#include "tools/study/statistics.h"

namespace nuld::study {

// The weighted least-squares slope of ln(error) over ln(spp), each point
// weighed by 1 / var(ln error) = (error / stderr)^2 (the delta method), and
// its standard error sqrt(1 / sum w (x - mean x)^2). Where a point has no
// standard error (one repeat) the fit is unweighted and its standard error
// the residuals' (NaN for three points on a line). NaN for fewer than three
// points, a non-positive error or fewer than two distinct spp.
Ratio convergenceSlope(std::span<const double> spp, std::span<const double> error,
                       std::span<const double> stderr_);

// OUT/slopes.csv's columns: scene, backend, spps (space-separated),
// mse_slope, mse_slope_stderr, screen_slope, screen_slope_stderr.
const std::vector<std::string> &slopeColumns();
// One row per scene and backend of a render study's table that has three
// or more spp values, in the table's order.
std::vector<std::vector<std::string>> slopeRows(const CsvTable &table);

}  // namespace nuld::study
