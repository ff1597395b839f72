#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "sampler/diagnostics.h"
#include "sampler/enum_names.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/metrics/integration.h"
#include "sampler/metrics/moment_spread.h"
#include "sampler/metrics/set_distance.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addEval(CLI::App &app) {
  struct Options {
    std::string file, target, metric = "all", integrand;
    int grid = 256;
    bool perInstance = false, zeroDensity = false, setDistance = false, prefixes = false,
         momentSpread = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->file, "point-set file")->required();
  app.add_option("--target", o->target,
                 targetOptionHelp("target SPEC (default: the file's, else uniform)"))
      ->check(targetFamily());
  app.add_option("--metric", o->metric,
                 "l2star, l2asd, dstar, l2 (grid L2asd against the target), l2per (periodic "
                 "L2, uniform target only) or all")
      ->check(CLI::IsMember({"l2star", "l2asd", "dstar", "l2", "l2per", "all"}))
      ->capture_default_str();
  app.add_option("--grid", o->grid, "grid resolution of the non-uniform L2 measures")
      ->check(wholeNumberIn(1, 4096))
      ->capture_default_str();
  app.add_flag("--per-instance", o->perInstance, "also print each instance's values");
  app.add_flag("--prefixes", o->prefixes,
               "also print each metric of the instances' first M points as METRIC@M, for M = "
               "1, 2, 4, ... below N (nested files: their prefix sizes, always printed)");
  app.add_flag(
      "--zero-density", o->zeroDensity,
      "print only zero_density_fraction: the share of points where the target's density is 0");
  app.add_flag("--set-distance", o->setDistance,
               "also print set_distance: the mean chamfer distance between instances (distinct "
               "sets score ~0.5/sqrt(N); near 0 means the instances are the same set)");
  app.add_flag("--moment-spread", o->momentSpread,
               "also print moment_spread_x, _y and _xy: over the instances, the standard "
               "deviation of each set's mean x, y and x y (sets that drift as a whole score high; "
               "compare with Owen-Sobol's at the same N)");
  app.add_option("--integrand", o->integrand,
                 "also estimate the integral of a test integrand (step, disc, bilinear, gaussian) "
                 "with the points as importance samples of the target; prints its RMSE and bias")
      ->check(parsedBy(makeTestIntegrand));
  app.footer(
      "Values are plain (not squared) discrepancies, averaged over the file's instances.\n"
      "Against a uniform target l2star, l2asd and l2per are exact closed forms; against a\n"
      "non-uniform one l2star and l2asd integrate on a grid. dstar is exact either way.");
  return [o] {
    // Every name checked before any value prints.
    std::optional<TestIntegrand> integrand;
    if (!o->integrand.empty()) integrand = makeTestIntegrand(o->integrand);
    const PointSet set = readPointSet(o->file);
    const auto target = targetFor(o->target, set, o->file);
    const bool uniform = target->isUniform();
    if (integrand) {
      // The test integrands live on the unit square.
      if (target->domain() != Domain::Square)
        throw std::invalid_argument(o->file + ": --integrand " + o->integrand +
                                    " integrates over the unit square, but the points follow '" +
                                    target->spec() + "' on the " + toString(target->domain()));
      // Where the integrand has mass but the target none, no point can
      // land: the estimate misses that mass, whatever the points.
      constexpr int kGrid = 256;
      double missed = 0;
      for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
          const Point2 p{(i + 0.5) / kGrid, (j + 0.5) / kGrid};
          if (target->pdf(p) <= 0) missed += std::abs(integrand->f(p)) / (kGrid * kGrid);
        }
      if (missed > 1e-3 * std::abs(integrand->integral))
        warning(o->file + ": the target '" + target->spec() + "' has no density where " +
                o->integrand + " holds " + std::to_string(missed) +
                " of its integral: integration_bias includes that missed mass");
    }
    if (o->zeroDensity) {
      std::size_t zero = 0;
      for (const Point2 &p : set.points) zero += target->pdf(p) <= 0;
      std::printf("zero_density_fraction %.9g\n", double(zero) / double(set.points.size()));
      return 0;
    }
    std::vector<std::string> metrics;
    if (o->metric == "all") {
      metrics = {"l2star", "l2asd", "dstar", "l2"};
      if (uniform) metrics.push_back("l2per");
    } else {
      metrics = {o->metric};
    }
    if (o->metric == "l2per" && !uniform)
      throw std::invalid_argument(o->file +
                                  ": --metric l2per measures uniform sets on the torus; "
                                  "the target is '" +
                                  target->spec() + "'");
    // Prefix sizes: a nested file's own, or powers of 2 when asked.
    std::vector<std::size_t> prefixes;
    if (const std::string *listed = findMeta(set, meta::kPrefixes))
      prefixes = parseSizeList(o->file + ": metadata 'prefixes'", *listed);
    else if (o->prefixes)
      for (std::size_t m = 1; m < set.n; m *= 2) prefixes.push_back(m);
    std::erase_if(prefixes, [&](std::size_t m) { return m >= set.n; });
    for (const std::string &m : metrics) {
      double sum = 0;
      for (std::size_t k = 0; k < set.instances(); ++k) {
        const auto pts = set.instance(k);
        const double v = discrepancyByName(m, pts, *target, o->grid);
        if (o->perInstance) std::printf("%s[%zu] %.9g\n", m.c_str(), k, v);
        sum += v;
      }
      std::printf("%s %.9g\n", m.c_str(), sum / double(set.instances()));
      for (const std::size_t size : prefixes) {
        double prefixSum = 0;
        for (std::size_t k = 0; k < set.instances(); ++k)
          prefixSum += discrepancyByName(m, set.instance(k).first(size), *target, o->grid);
        std::printf("%s@%zu %.9g\n", m.c_str(), size, prefixSum / double(set.instances()));
      }
    }
    if (o->setDistance) std::printf("set_distance %.9g\n", meanSetDistance(set));
    if (o->momentSpread) {
      const MomentSpread m = momentSpread(set);
      std::printf("moment_spread_x %.9g\nmoment_spread_y %.9g\nmoment_spread_xy %.9g\n", m.x, m.y,
                  m.xy);
    }
    if (integrand) {
      const TestIntegrand &f = *integrand;
      double se = 0, bias = 0;
      for (std::size_t k = 0; k < set.instances(); ++k) {
        const double err = estimateIntegral(set.instance(k), *target, f.f) - f.integral;
        se += err * err;
        bias += err;
      }
      const double K = double(set.instances());
      std::printf("integration_rmse %.9g\nintegration_bias %.9g\n", std::sqrt(se / K), bias / K);
    }
    return 0;
  };
}

}  // namespace nuld::cli
