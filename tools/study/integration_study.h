#pragma once
// `nuld study integrate`: integration error against N for the study's
// integrands (integrands.h), sampler against sampler, over many randomized
// instances, one CSV row per (integrand, sampler, N).
//
// Samplers (the CSV's `sampler` values):
//   independent, sobol (Owen-scrambled), halton (Owen-scrambled digits):
//       uniform points in each sampler's own mapping, as in nuld render: on
//       integrands with a BRDF its own sample() (lobe picked by u.x,
//       one-sample MIS over lobes: the supplement's baseline), on the others
//       the target's inverse CDF;
//   independent-tabulated, sobol-tabulated, halton-tabulated: on integrands
//       with a BRDF, the same points through the tabulated lobe's inverse CDF;
//   optimized: Algorithm 1 at each N with the target's default preset, cached
//       in the shared set cache (backends/set_cache.h), keyed by the
//       target's content and the settings;
//   neural:NAME: a trained model (NAME = its file's stem) at its own N, on the
//       integrands whose target it was trained for, fresh z per instance;
//   optimized:PATHS, shifted:PATHS: the sets of point-set files, as nuld
//       render deals them out (backends/backend_registry.h), at their own N.
// Conventional samplers average `instances` instances, optimized and neural
// ones `optimizedInstances` (the supplement's 128 and 16).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "backends/optimized_sets.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "tools/study/csv_table.h"
#include "tools/study/integrands.h"

namespace nuld::study {

// integrand,domain,sampler,n,instances,reference,mean,bias,bias_stderr,std,
// rmse,rel_rmse,mse_stderr,gen_seconds_per_set,setup_seconds_per_set
const std::vector<std::string> &integrateColumns();
std::filesystem::path integrateCsvPath(const std::filesystem::path &outDir);

struct IntegrateOptions {
  std::filesystem::path outDir;
  std::vector<std::string> integrands;  // kinds or full names; empty: all
  std::vector<std::string> samplers;    // empty: independent, sobol, halton, optimized
  std::vector<std::size_t> ns{16, 32, 64, 128, 256, 512, 1024, 2048, 4096};
  std::size_t instances = 128;
  std::size_t optimizedInstances = 16;
  // Larger N are left out for `optimized`: Algorithm 1's cost grows with N
  // times the boxes (and the preset doubles the boxes at N >= 2048).
  std::size_t optimizedMaxN = 1024;
  int optEpochs = 0;                         // 0: the preset's
  std::optional<Objective> optObjective;     // nullopt: the preset's
  double optUnionWeight = kBankUnionWeight;  // the bank term, with the l2asd objective
  std::vector<std::string> neuralModels;
  std::string assetRoot;  // resolved; maps are looked up in ASSETROOT/envmaps
  std::vector<std::string> envmaps{"grace"};
  // Whether the user named the maps: a named map that is not found is an
  // error; the default one is skipped with a note.
  bool envmapsNamed = false;
  std::uint64_t seed = 0;
  // How the Disney integrands' own lobe sampling (the sobol-lobes row)
  // picks a lobe (--lobe-choice; materials/disney.h).
  LobeChoice lobeChoice = kDefaultLobeChoice;
  // The set cache's directory (set_cache.h); empty: SetCache::fromEnvironment.
  std::filesystem::path cacheDir;
};

// What a row depends on beyond its integrand, sampler and N, as the
// command's option names: a rerun asking for other values is refused
// (CsvTable::requireOptions).
std::string rowOptions(const IntegrateOptions &o);

// "16,32,100": positive integers, comma-separated. Throws
// std::invalid_argument naming --n and what was expected.
std::vector<std::size_t> parseNList(const std::string &text);
// "a,b,c" -> {a, b, c}, blanks trimmed, empty items dropped.
std::vector<std::string> splitList(const std::string &text);

struct SamplerChoice {
  enum class Kind { Classic, Optimized, Neural, BlueNoise, Bank };
  std::string name;  // the CSV value
  Kind kind = Kind::Classic;
  bool tabulated = false;  // a lobe integrand's table, not the BRDF's own sample()
  std::string model;       // Neural: the model file
  // Bank: the renderer's optimized:PATHS / points:PATHS / shifted:PATHS, the
  // point-set files or directories; for banks and neural models, whether
  // sets are shifted.
  std::string paths;
  bool shifted = false;
  // Classic: the sampler and its randomization (sequence.h).
  SequenceKind sequence = SequenceKind::Sobol;
  Scramble scramble = Scramble::Owen;
};

// Tokens: the backend registry's words that serve the integration study
// (backends/backend_registry.h, parsed there; a word means what it means in
// renders): independent|random, sobol, halton and each -tabulated (on lobe
// integrands through the tabulated lobe's inverse CDF), stratified, pmj02,
// lattice, lattice-baker, optimized (sets
// optimized for each integrand's target), optimized:PATHS|points:PATHS and
// shifted:PATHS (sets from files, on the integrands whose target they
// follow; uniform sets on every integrand, shifted per instance and mapped
// by its inverse CDF), the blue-noise sot, sot-mapped, gbn, gbn-mapped, and
// neural[:MODEL] (without MODEL the shipped model, shippedLobeModel; with
// +shift every set shifted in primary space per instance, as the renderer
// deals them out; runIntegrateStudy shifts a lobe family's sets as renders
// do and names the row so). The default is every classic word and
// optimized. Throws std::invalid_argument naming --samplers and the
// accepted names; the old -lobes spellings are refused with their new names.
std::vector<SamplerChoice> parseSamplers(const std::vector<std::string> &tokens,
                                         const std::vector<std::string> &models);

// The importance-sampling estimate (1/N) sum f(x_i) / p(x_i). A point where
// p is 0 (or f / p is not finite) adds 0 and is counted in `zeroPdf`: a set
// that leaves its target's support shows up as bias, never as NaN.
double importanceEstimate(const Integrand &integrand, std::span<const Point2> points,
                          std::size_t &zeroPdf);

struct EstimateStats {
  double mean = 0, bias = 0, biasStderr = 0, std = 0, rmse = 0, relRmse = 0, mseStderr = 0;
};
// Over K >= 2 estimates: std with K - 1, bias_stderr = std / sqrt(K),
// rmse = sqrt(mean((e - ref)^2)), so rmse^2 = bias^2 + (K - 1) / K std^2;
// mse_stderr = the standard error of that mean of squared errors.
EstimateStats summarize(std::span<const double> estimates, double reference);

struct IntegrateHooks {
  std::function<void(const std::string &)> message;  // notes (skipped maps, zero-pdf counts)
  // Rows done of the total, and what is running now.
  std::function<void(long done, long total, const std::string &status)> progress;
};

struct IntegrateSummary {
  std::size_t rowsAdded = 0, rowsSkipped = 0;  // skipped: already in the CSV
  std::size_t setsOptimized = 0, setsFromCache = 0;
  std::vector<std::string> notes;  // every message, also those passed to hooks
};

// Runs the study into OUTDIR/integrate.csv, resuming it (rows present are
// skipped). Throws std::invalid_argument or std::runtime_error naming the
// option for an unknown integrand or sampler, a bad N list or instance
// count, an unreadable model, or a model that matches no integrand.
IntegrateSummary runIntegrateStudy(const IntegrateOptions &options,
                                   const IntegrateHooks &hooks = {});

// The integrands the options select, with their maps loaded; a sphere
// integrand whose map is missing is skipped with a note.
std::vector<Integrand> selectIntegrands(const IntegrateOptions &options,
                                        std::vector<std::string> &notes);

// Runs /usr/bin/python3 TOOLS/study/report.py OUTDIR (plot_integrate.py's plots and index.html;
// report_script.h: TOOLS is $NULD_TOOLS_DIR, else this checkout's tools/). Returns a warning when
// no plots were made (no python, matplotlib or script); the CSV stands.
std::optional<std::string> runIntegratePlots(const std::filesystem::path &outDir);

// Per integrand, RMSE by sampler (rows) and N (columns), from the CSV rows.
std::string rmseTable(const CsvTable &table);

}  // namespace nuld::study
