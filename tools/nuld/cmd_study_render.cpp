// nuld study render: scenes against references, every backend at every spp;
// nuld study report: the plots and the HTML page of a study directory.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <tuple>

#include "backends/ranks.h"
#include "backends/ready_backend.h"
#include "backends/reference_cache.h"
#include "renderer/image_metrics.h"
#include "renderer/path_integrator.h"
#include "renderer/render.h"
#include "sampler/io/output_folder.h"
#include "scenes/scene_file.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/interrupt_note.h"
#include "tools/nuld/progress.h"
#include "tools/study/baselines.h"
#include "tools/study/compare_page.h"
#include "tools/study/convergence.h"
#include "tools/study/csv_table.h"
#include "tools/study/equal_time.h"
#include "tools/study/render_study.h"
#include "tools/study/report_script.h"

namespace nuld::cli {

namespace {

// One bar per task; a new task closes the previous bar.
class TaskBars {
 public:
  explicit TaskBars(bool quiet) : quiet_(quiet) {}
  ~TaskBars() { close(); }
  void update(const std::string &task, double fraction, const std::string &status) {
    if (task != task_) {
      close();
      task_ = task;
      bar_ = std::make_unique<ProgressBar>(task, 1000, long(1000 * fraction), quiet_);
    }
    status_ = status;
    bar_->update(long(1000 * fraction), status);
  }
  void close() {
    if (bar_) bar_->finish(status_);
    bar_.reset();
    task_.clear();
  }

 private:
  bool quiet_;
  std::string task_, status_;
  std::unique_ptr<ProgressBar> bar_;
};

const char *verdictOf(double q, double se) { return study::verdictName(study::verdictOf(q, se)); }

// MSE per (scene, backend, spp), with the ratio to sobol at the same spp,
// the comparison the studies are about, to the best classic backend there
// (the baseline a learned backend must beat: tools/study/baselines.h), and
// at equal time (MSE x total seconds, setup amortized:
// tools/study/equal_time.h); then, per scene and spp, the backend with the
// lowest error for the time. Each scene's heading gives its reference's own
// noise; a row within 10x of it says so.
std::string formatRatio(double q, double se) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3f+-%.3f", q, se);
  return text;
}

void printTable(const study::CsvTable &table, const study::CsvTable &references, double amortize) {
  const std::vector<study::TimedRow> rows = study::timedRows(table);
  const std::vector<study::EqualTime> times = study::equalTime(rows, amortize);
  const std::size_t relmse = table.column("relmse"), classic = table.column("best_classic"),
                    classicRatio = table.column("mse_ratio_best_classic"),
                    classicStderr = table.column("mse_ratio_best_classic_stderr"),
                    tooNoisy = table.column("reference_too_noisy"),
                    breakEven = table.column("break_even_renders"),
                    screen = table.column("screen_mse"),
                    screenSobol = table.column("screen_ratio_sobol"),
                    screenSobolStderr = table.column("screen_ratio_sobol_stderr"),
                    screenClassic = table.column("screen_ratio_best_classic"),
                    screenClassicStderr = table.column("screen_ratio_best_classic_stderr"),
                    flipMean = table.column("flip"), flipSobol = table.column("flip_ratio_sobol"),
                    flipSobolStderr = table.column("flip_ratio_sobol_stderr");
  std::map<std::pair<std::string, std::size_t>, const study::TimedRow *> sobol;
  for (const auto &r : rows)
    if (r.backend == "sobol") sobol[{r.scene, r.spp}] = &r;
  std::map<std::string, const std::vector<std::string> *> reference;
  for (const auto &r : references.rows()) reference[r[references.column("scene")]] = &r;
  // Rows are made spp by spp; the table reads backend by backend.
  std::map<std::string, std::size_t> sceneOrder, backendOrder;
  for (const auto &r : rows) {
    sceneOrder.emplace(r.scene, sceneOrder.size());
    backendOrder.emplace(r.backend, backendOrder.size());
  }
  std::vector<std::size_t> order(rows.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tuple(sceneOrder[rows[a].scene], backendOrder[rows[a].backend], rows[a].spp) <
           std::tuple(sceneOrder[rows[b].scene], backendOrder[rows[b].backend], rows[b].spp);
  });
  // The backend column is as wide as the longest word or label: none is cut.
  int width = 22, classicWidth = 15;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    width = std::max(width, int(rowLabel(rows[i].backend).size()));
    classicWidth = std::max(classicWidth, int(rowLabel(table.rows()[i][classic]).size()));
  }
  std::string lastScene;
  for (const std::size_t i : order) {
    const study::TimedRow &r = rows[i];
    const std::vector<std::string> &csv = table.rows()[i];
    if (r.scene != lastScene) {
      std::printf("\n%s", r.scene.c_str());
      if (const auto ref = reference.find(r.scene); ref != reference.end()) {
        const auto value = [&](const char *column) {
          return (*ref->second)[references.column(column)];
        };
        std::printf(
            " (reference: %s, %s spp%s, own variance %.4e, relMSE %.4e)", value("backend").c_str(),
            value("spp").c_str(), value("cache") == "found" ? ", found in the cache" : "",
            study::parseNumber(value("variance")), study::parseNumber(value("relvariance")));
      }
      // mse*s/sobol: the MSE times the total seconds over sobol's, the
      // equal-time comparison (equal_time_ratio in render.csv).
      std::printf(
          "\n%-*s %5s %5s %-9s %11s %11s %13s %6s %13s %6s %-*s %15s %8s %8s %13s %6s %6s %11s "
          "%13s %6s %13s %11s %13s %6s\n",
          width, "backend", "spp", "reps", "stop", "mse", "relmse", "mse/sobol", "vs",
          "mse/classic", "vs", classicWidth, "best_classic", "median_s+-mad", "setup_s", "total_s",
          "mse*s/sobol", "vs", "pays@", "screen", "scr/sobol", "vs", "scr/classic", "flip",
          "flip/sobol", "vs");
      lastScene = r.scene;
    }
    const auto it = sobol.find({r.scene, r.spp});
    char ratio[48] = "-", timeRatio[48] = "-", classicText[48] = "-", paysAt[24] = "-";
    const char *verdict = "-", *timeVerdict = "-", *classicVerdict = "-";
    if (it != sobol.end() && it->second->mse > 0 && r.backend != "sobol") {
      // A verdict needs two standard errors between the ratio and 1.
      const study::Ratio q =
          study::ratioOfMeans(r.mse, r.mseStderr, it->second->mse, it->second->mseStderr);
      std::snprintf(ratio, sizeof ratio, "%.3f+-%.3f", q.value, q.stderr_);
      verdict = verdictOf(q.value, q.stderr_);
      std::snprintf(timeRatio, sizeof timeRatio, "%.3f+-%.3f", times[i].ratio,
                    times[i].ratioStderr);
      timeVerdict = verdictOf(times[i].ratio, times[i].ratioStderr);
    } else if (it != sobol.end()) {
      std::snprintf(ratio, sizeof ratio, "1");
      std::snprintf(timeRatio, sizeof timeRatio, "1");
    }
    // Learned and plugin rows only (the built-in classic ones have no ratio
    // to the best classic; a plugin's pays@ is "-": it has no setup).
    const double cq = study::parseNumber(csv[classicRatio]),
                 cse = study::parseNumber(csv[classicStderr]);
    if (std::isfinite(cq)) {
      std::snprintf(classicText, sizeof classicText, "%.3f+-%.3f", cq, cse);
      classicVerdict = verdictOf(cq, cse);
      const double k = study::parseNumber(csv[breakEven]);
      if (std::isinf(k))
        std::snprintf(paysAt, sizeof paysAt, "never");
      else if (std::isfinite(k))
        std::snprintf(paysAt, sizeof paysAt, "%.0f", k);
    }
    // A measured error's mean and its ratio to sobol's with the verdict,
    // for the screen error and HDR-FLIP ("-" where an older file lacks
    // them; sobol's own row reads 1, as its mse/sobol does).
    struct Measured {
      char mean[24] = "-", toSobol[48] = "-";
      const char *verdict = "-";
    };
    const auto measured = [&](std::size_t meanColumn, std::size_t ratioColumn,
                              std::size_t stderrColumn) {
      Measured m;
      const double v = study::parseNumber(csv[meanColumn]);
      if (!std::isfinite(v)) return m;
      std::snprintf(m.mean, sizeof m.mean, "%.4e", v);
      if (r.backend == "sobol") {
        std::snprintf(m.toSobol, sizeof m.toSobol, "1");
      } else if (const double q = study::parseNumber(csv[ratioColumn]); std::isfinite(q)) {
        const double se = study::parseNumber(csv[stderrColumn]);
        std::snprintf(m.toSobol, sizeof m.toSobol, "%.3f+-%.3f", q, se);
        m.verdict = verdictOf(q, se);
      }
      return m;
    };
    const Measured screenError = measured(screen, screenSobol, screenSobolStderr),
                   flip = measured(flipMean, flipSobol, flipSobolStderr);
    char screenClassicText[48] = "-";
    if (const double q = study::parseNumber(csv[screenClassic]); std::isfinite(q))
      std::snprintf(screenClassicText, sizeof screenClassicText, "%.3f+-%.3f", q,
                    study::parseNumber(csv[screenClassicStderr]));
    // What the row's flags say, after its columns.
    std::string flags = csv[tooNoisy] == "1" ? "  reference too noisy for this row" : "";
    if (csv[table.column("ruled_by_outliers")] == "1")
      flags += "  ruled by outliers: winsorized/classic " +
               formatRatio(
                   study::parseNumber(csv[table.column("winsorized_ratio_best_classic")]),
                   study::parseNumber(csv[table.column("winsorized_ratio_best_classic_stderr")]));
    const std::string stop =
        csv[table.column("stopped_on")].empty() ? "-" : csv[table.column("stopped_on")];
    char seconds[40];
    const double mad = study::parseNumber(csv[table.column(study::timeSpreadColumns()[0])]);
    std::snprintf(seconds, sizeof seconds, std::isfinite(mad) ? "%.3f+-%.3f" : "%.3f", r.seconds,
                  mad);
    std::printf(
        "%-*s %5zu %5s %-9s %11.4e %11.4e %13s %6s %13s %6s %-*s %15s %8.2f %8.3f %13s %6s %6s "
        "%11s %13s %6s %13s %11s %13s %6s%s\n",
        width, rowLabel(r.backend).c_str(), r.spp, csv[table.column("repeats")].c_str(),
        stop.c_str(), r.mse, study::parseNumber(csv[relmse]), ratio, verdict, classicText,
        classicVerdict, classicWidth, csv[classic].empty() ? "-" : rowLabel(csv[classic]).c_str(),
        seconds, r.setupSeconds, times[i].totalSeconds, timeRatio, timeVerdict, paysAt,
        screenError.mean, screenError.toSobol, screenError.verdict, screenClassicText, flip.mean,
        flip.toSobol, flip.verdict, flags.c_str());
  }
  // Convergence rates, where a row has three or more spp values.
  if (const auto slopes = study::slopeRows(table); !slopes.empty()) {
    std::printf(
        "\nConvergence rates (slope of log error over log spp; Monte Carlo's MSE has -1):\n");
    std::printf("    %-*s %-16s %16s %16s\n", width, "backend", "spp", "mse slope", "screen slope");
    std::string scene;
    for (const auto &r : slopes) {
      if (r[0] != scene) std::printf("  %s\n", (scene = r[0]).c_str());
      const auto slope = [](const std::string &v, const std::string &e) {
        const double s = study::parseNumber(v), se = study::parseNumber(e);
        char text[48] = "-";
        if (std::isfinite(s)) std::snprintf(text, sizeof text, "%.3f+-%.3f", s, se);
        return std::string(text);
      };
      std::printf("    %-*s %-16s %16s %16s\n", width, r[1].c_str(), r[2].c_str(),
                  slope(r[3], r[4]).c_str(), slope(r[5], r[6]).c_str());
    }
  }
  std::printf("\nLowest error for the time (MSE x total seconds, setup over %s render%s):\n",
              formatNumber(amortize).c_str(), amortize == 1 ? "" : "s");
  for (const study::TimeVerdict &v : study::timeVerdicts(rows, amortize))
    std::printf("  %s\n", study::describe(v).c_str());
}

int runReport(const std::string &dir) {
  requireOwnedFolder(dir, study::kStudyFolder);
  // The comparison page first: the report links to it.
  if (const std::filesystem::path page =
          study::writeComparisonPage(dir, study::toolsDir() / "study" / "compare");
      !page.empty())
    std::printf("comparison page: %s\n", page.string().c_str());
  std::fflush(stdout);  // before the report script's own lines
  std::string why;
  const int status = study::runStudyScript("report.py", dir, &why);
  if (status < 0) {
    std::cerr << "nuld: warning: no plots or report: " << why << "\n";
    return 0;
  }
  if (status != 0) std::cerr << "nuld: error: report.py exited with status " << status << "\n";
  return status == 0 ? 0 : 1;
}

}  // namespace

Runner addStudyRender(CLI::App &app) {
  struct Options {
    study::RenderStudySettings s;
    std::string res, integrator, out;
    bool noReport = false, quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scenes", o->s.scenes,
                 "scene files (JSON, or glTF .gltf/.glb) or a built-in scene: " +
                     builtInSceneList() + " (default: default)");
  app.add_option("--backends", o->s.backends,
                 "comma-separated backend words: " + backendSpellings(kRenders) +
                     " (optimized without PATHS: sets for the scene's environment map; "
                     "optimized-bsdf: lobe banks for the scene's Disney materials; each made once "
                     "into the set cache, and each also with the suffix +shift: sets randomized "
                     "in primary space; LABEL=WORD names a row LABEL in tables and files; nuld "
                     "help backends)")
      ->delimiter(',')
      ->check(studyBackendWord());
  app.add_option("--spp", o->s.spp, "comma-separated samples per pixel (default 4,16,64)")
      ->delimiter(',');
  app.add_option("--reference-spp", o->s.reference.spp,
                 "reference samples per pixel (default 4096; the paper: 2^17 lte-orb, 2^13 "
                 "dragon, 2^16 cup)")
      ->check(positiveNumber());
  app.add_option("--reference-pass-spp", o->s.reference.passSpp,
                 "reference spp per resumable pass (default 256)")
      ->check(positiveNumber());
  app.add_option("--reference-stop-after", o->s.referenceStopAfter,
                 "render at most this many reference passes in this run, then stop with the "
                 "reference saved (a rerun continues it; for job time limits)")
      ->check(positiveNumber());
  app.add_option("--reference-backend", o->s.reference.backend,
                 "backend of the reference (default halton, as the paper)")
      ->check(backendWord());
  app.add_option("--res", o->res,
                 "resolution WxH, or W keeping each scene's aspect (default: the scene's)")
      ->check(parsedBy(parseResolution));
  app.add_option("--res-scale", o->s.render.resolutionScale,
                 "scale each scene's own resolution (e.g. 0.25; not with --res)")
      ->check(numberIn(1e-6, 16));
  app.add_option("--integrator", o->integrator,
                 "path, direct (MIS), light or bsdf (default: the scene's)")
      ->check(oneOf(kIntegratorNames));
  app.add_option("--max-depth", o->s.render.maxDepth, "maximum path length")
      ->check(wholeNumberIn(1, kMaxDepthLimit));
  app.add_option("--repeats", o->s.repeats,
                 "renders per (backend, spp) with seeds seed, seed+1, ...; MSE is their mean "
                 "(with --target-stderr: the first round's)")
      ->check(positiveNumber());
  app.add_option("--target-stderr", o->s.budget.targetStderr,
                 "add repeats, in rounds, to the rows whose MSE ratio to the best classic row "
                 "or to sobol has a standard error above this share of the ratio (e.g. 0.05: "
                 "+-5 %), until none has or the budget is spent; repeat r keeps seed + r, so a "
                 "rerun is bit-identical "
                 "(default 0: fixed repeats)")
      ->check(numberIn(0, 1e6));
  app.add_option("--max-repeats", o->s.budget.maxRepeats,
                 "with --target-stderr: the most repeats of any row (default 64)")
      ->check(positiveNumber());
  app.add_option("--budget-seconds", o->s.budget.seconds,
                 "with --target-stderr: the most seconds of added repeats per scene; a round "
                 "that would overrun them is not started (default 0: no limit)")
      ->check(numberIn(0, 1e9));
  app.add_option("--seed", o->s.seed,
                 "seed of the backends (default " + std::to_string(kDefaultSeed) +
                     ", as nuld render's and nuld bank's)")
      ->check(wholeNumber());
  app.add_option("--amortize", o->s.amortize,
                 "renders the setup of a backend's sets is spread over in total_seconds and "
                 "equal_time_ratio (default 1: every render pays it all; pass the number of "
                 "frames or views you will render with the same sets)")
      ->check(CLI::Range(1.0, 1e12));
  addSetOptions(app, o->s.sets);
  addLobeOptions(app, o->s.render);
  addSceneChoiceOptions(app, o->s.choices);
  app.add_option("--assets", o->s.assets,
                 "asset root (default: $NULD_ASSETS, else ../shared/assets)");
  app.add_option("-o,--output", o->out, "study directory (created; a rerun resumes it)")
      ->required();
  app.add_flag("--no-report", o->noReport, "skip the plots and the HTML report");
  app.add_flag("-q,--quiet", o->quiet, "no progress bars");
  app.footer(
      "Writes OUT/render.csv (one row per scene, backend, spp: mse, relmse with standard errors\n"
      "over the repeats, seconds per render including the backend's sample generation,\n"
      "setup_seconds of one-off optimization, the MSE less the reference's own variance, the\n"
      "ratio to the best classic backend), OUT/verdicts.csv, OUT/references.csv (with the\n"
      "reference's variance from its two halves), OUT/SCENE/*.exr|png and, unless\n"
      "--no-report, OUT/plots/*.png and OUT/index.html (open it in a browser).");
  return [o, &app] {
    study::RenderStudySettings s = o->s;
    s.out = o->out;
    if (s.scenes.empty()) s.scenes = {"default"};
    // Which options apply, asked of the parsed words (render_study.h).
    std::vector<BackendWord> words;
    for (const std::string &b : s.backends) words.push_back(parseBackendWord(b));
    const auto anyBackend = [&](bool (BackendWord::*has)() const) {
      return std::any_of(words.begin(), words.end(),
                         [&](const BackendWord &w) { return (w.*has)(); });
    };
    checkAssets(app, s.assets, !std::all_of(s.scenes.begin(), s.scenes.end(), isBuiltInScene),
                kSceneFilesOnly);

    onlyWhen(app, s.budget.targetStderr > 0, {"--max-repeats", "--budget-seconds"},
             "--target-stderr above 0");
    onlyWhen(app, anyBackend(&BackendWord::makesSets),
             {"--opt-instances", "--opt-epochs", "--opt-nested"},
             "the sets the study optimizes (backends optimized, optimized-uniform, "
             "optimized-bsdf, optimized-both)");
    onlyWhen(app, anyBackend(&BackendWord::makesLobeSets), {"--opt-lobe-epochs"},
             "the lobe banks (backends optimized-bsdf, optimized-both)");
    onlyWhen(app, anyBackend(&BackendWord::makesEnvSets), {"--opt-objective"},
             "the environment-map sets (backends optimized, optimized-both)");
    onlyWhen(
        app,
        anyBackend(&BackendWord::makesLobeSets) || (anyBackend(&BackendWord::makesEnvSets) &&
                                                    s.sets.envObjective == Objective::ExactL2asd),
        {"--opt-union-weight"},
        "banks optimized for the exact L2asd (backends optimized-bsdf, optimized-both, "
        "and optimized with --opt-objective l2asd)");
    // Asked only when a --lobe-* option is given: it reads the files a bank
    // word names, on every rank, before the study reads them cell by cell.
    const bool lobeOptionGiven = std::any_of(kLobeOptionNames.begin(), kLobeOptionNames.end(),
                                             [&](const char *name) { return app.count(name) > 0; });
    onlyWhen(app, !lobeOptionGiven || anyBackend(&BackendWord::samplesLobes), kLobeOptionNames,
             "backends that sample lobe tables (sobol-tabulated, the study's sets but "
             "optimized-uniform, neural, and banks of lobe sets)");
    onlyWhen(app, !app.count("--integrator") || o->integrator == "path", {"--max-depth"},
             "--integrator path");
    applyResolution(app, o->res, s.render.resolutionScale, s.render);
    if (!o->integrator.empty()) s.render.integrator = parseIntegrator(o->integrator);

    // In a job of several ranks (mpirun, srun) rank 0 alone reports.
    const Ranks &ranks = Ranks::world();
    study::RenderStudyResult result;
    {
      // References and sets keep checkpoints (passes under OUT, sets in the
      // set cache), and a rerun continues them by itself.
      const InterruptNote interruptNote(
          s.out.string(), "the study keeps its reference passes in the reference cache (" +
                              ReferenceCache::fromEnvironment().referencesDir().string() +
                              ") and the checkpoints of sets being made in " +
                              setsDirectory(s.sets) + ": run the same command again to continue");
      TaskBars bars(o->quiet || !ranks.root());
      result = study::runRenderStudy(
          s, [&](const std::string &task, double f, const std::string &status) {
            bars.update(task, f, status);
          });
    }
    if (!ranks.root()) return 0;
    for (const auto &skip : result.skipped) std::cerr << "skipped " << skip << "\n";
    for (const auto &note : result.notes) std::cerr << "note: " << note << "\n";
    for (const auto &found : result.referencesFound)
      std::cerr << "note: the reference of " << found
                << " was found in the reference cache: no pass rendered, 0 s counted\n";
    for (const auto &scene : result.referencesIncomplete)
      std::cerr << "note: " << scene << ": the reference stopped after --reference-stop-after "
                << s.referenceStopAfter << " passes; run the same command again to continue it\n";
    study::CsvTable table(result.csv, study::renderStudyColumns(),
                          study::renderStudyDerivedColumns());
    table.loadExisting();
    if (table.rows().empty()) return 0;
    study::CsvTable references(result.csv.parent_path() / "references.csv",
                               study::referenceColumns(), study::referenceOptionalColumns());
    references.loadExisting();
    printTable(table, references, s.amortize);
    std::printf(
        "\n(MSE against the reference; mse/sobol < 1 beats Owen-Sobol at equal spp, +- its\n"
        " standard error over the repeats; vs: better or worse than sobol by more than two\n"
        " standard errors, else tie; n/a with one repeat. mse/classic, vs: a learned or plugin\n"
        " row against the built-in classic backend (best_classic) with the lowest MSE at that\n"
        " spp. A row whose MSE is below\n"
        " %gx the reference's own variance is marked: there the reference's noise, part of\n"
        " every MSE, decides the comparison. median_s+-mad: the median seconds of one render\n"
        " incl. the backend's sample generation, and their median absolute deviation, over\n"
        " repeats rendered interleaved across rows (every row's repeat 1, then every row's\n"
        " repeat 2, ...); setup_s: making this row's sets and lobe tables in this run (0 when\n"
        " cached); total_s: median_s + setup_s / --amortize; mse*s/sobol: MSE x total_s over\n"
        " sobol's, below 1 reaching sobol's error sooner, its vs counting the times' error as\n"
        " well as the MSEs' (a machine whose load varies gives a tie). pays@: a learned row's\n"
        " break_even_renders, the fewest renders sharing its setup after which it reaches\n"
        " the best classic row's error sooner (never: it is not ahead per render). screen:\n"
        " the MSE of the error image low-passed by a Gaussian of 1 pixel, the error a viewer\n"
        " sees (blue-noise error fades); scr/sobol, vs: its ratio to sobol's; scr/classic: to\n"
        " the classic row with the lowest screen error. flip, flip/sobol, vs: HDR-FLIP's mean\n"
        " (nuld compare) and its ratio to sobol's. reps: the row's repeats; stop: fixed\n"
        " (--repeats), precision (the relative error of every MSE ratio within\n"
        " --target-stderr) or budget (not, when --max-repeats or --budget-seconds ran\n"
        " out). Ruled by outliers: the MSE ratio to the\n"
        " best classic row and that of the MSE with each image's largest %g %% of pixel errors\n"
        " winsorized reach different verdicts: a few pixels decide it. CSV: %s)\n",
        study::kTooNoisyFactor, 100 * kWinsorizedShare, result.csv.string().c_str());
    std::fflush(stdout);  // the table before the report script's own lines
    return o->noReport ? 0 : runReport(o->out);
  };
}

Runner addStudyReport(CLI::App &app) {
  auto dir = std::make_shared<std::string>();
  app.add_option("dir", *dir, "study directory (holding render.csv and/or integrate.csv)")
      ->required();
  app.footer("Writes DIR/plots/*.png and DIR/index.html from the study's CSV files.");
  return [dir] { return runReport(*dir); };
}

}  // namespace nuld::cli
