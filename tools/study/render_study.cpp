#include "tools/study/render_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "backends/optimized_sets.h"
#include "backends/ranks.h"
#include "backends/reference_cache.h"
#include "backends/set_plans.h"
#include "backends/stopwatch.h"
#include "renderer/image_metrics.h"
#include "renderer/lobe_tables.h"
#include "renderer/sampler_backend.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/image_io.h"
#include "sampler/io/input_file.h"
#include "sampler/io/output_folder.h"
#include "sampler/targets/target_spec.h"
#include "scenes/scene_file.h"
#include "tools/study/adaptive_repeats.h"
#include "tools/study/baselines.h"
#include "tools/study/convergence.h"
#include "tools/study/csv_table.h"
#include "tools/study/equal_time.h"
#include "tools/study/render_cells.h"
#include "tools/study/statistics.h"

namespace nuld::study {

namespace fs = std::filesystem;

namespace {

ReferenceSettings referenceFor(const RenderStudySettings &s, const RenderSettings &render) {
  ReferenceSettings r = s.reference;
  r.render = render;
  return r;
}

// The scene's row, replacing one of an earlier reference (one rendered
// again after the old one was refused). `seconds` is what this study spent
// on it: 0 for a reference found in the cache, or kept from the run that
// rendered it; made_seconds is its render time over every run.
void putReferenceRow(CsvTable &refs, const std::string &scene, const ReferenceSettings &r,
                     const CachedReference &ref, const fs::path &image) {
  const std::string key = referenceKey(ref.description);
  const std::size_t sceneColumn = refs.column("scene"), keyColumn = refs.column("key");
  for (const auto &row : refs.rows())
    if (row[sceneColumn] == scene && row[keyColumn] == key) return;
  refs.putRow({scene, r.backend, std::to_string(r.totalSpp()),
               std::to_string(r.render.width) + "x" + std::to_string(r.render.height),
               toString(r.render.integrator), formatNumber(ref.result.noise.variance),
               formatNumber(ref.result.noise.relVariance),
               formatNumber(ref.found ? 0.0 : ref.result.seconds), image.string(),
               formatNumber(ref.result.totalSeconds), ref.found ? "found" : "rendered", key,
               ref.dir.string()},
              1);
}

// The reference's files in the study's folder, as links to the cache's (a
// copy where the cache is on another file system), so that the study's
// folder keeps its reference when the cache is cleared. A reference already
// there of another description is refused: the rows beside it were scored
// against it.
void placeReference(const CachedReference &ref, const fs::path &dir) {
  fs::create_directories(dir);
  const fs::path main = dir / "reference.exr";
  if (fs::exists(main)) {
    std::string recorded;
    for (const auto &[name, value] : readImageAttributes(main.string()))
      if (name == "nuld:reference") recorded = value;
    if (recorded != ref.description)
      throw std::runtime_error(
          main.string() + ": made with '" + recorded + "', but this study asks for '" +
          ref.description +
          "' (use another output directory: the rows beside it were scored against it)");
  }
  for (const char *name :
       {"reference.half0.exr", "reference.half1.exr", "reference.png", "reference.exr"}) {
    const fs::path from = ref.dir / name, to = dir / name;
    std::error_code ec;
    if (!fs::exists(from) || fs::equivalent(from, to, ec)) continue;
    copyFileAtomically(from, to, true);
  }
}

// Each scene's reference noise, as references.csv records it (also for
// scenes of earlier runs).
std::map<std::string, ReferenceNoise> referenceNoiseByScene(const CsvTable &refs) {
  std::map<std::string, ReferenceNoise> out;
  const std::size_t scene = refs.column("scene"), variance = refs.column("variance"),
                    relVariance = refs.column("relvariance");
  for (const auto &row : refs.rows())
    out[row[scene]] = {parseNumber(row[variance]), parseNumber(row[relVariance])};
  return out;
}

// The columns computed over the whole table, after every row.
void fillDerivedColumns(CsvTable &table, const CsvTable &refs, double amortize) {
  fillEqualTime(table, amortize);
  fillBaselineColumns(table, referenceNoiseByScene(refs));
}

}  // namespace

namespace {

// The pipeline of one scene: its reference, then the plan of the cells still
// missing from the table, then their sets, then the cells. Every rank runs
// every stage on the same values (MPI: backends/ranks.h); the sets and
// the cells are split over the ranks.

// One scene as the stages see it.
struct SceneStudy {
  LoadedScene loaded;
  RenderSettings settings;  // the study's overrides applied
  std::string slug;
  fs::path dir;
};

// A cell still to render and what its backend needs at its spp.
struct PlannedCell {
  BackendWord backend;
  std::size_t spp;
  BackendPlan plan;
  bool samplesLobes;        // its setup includes the lobe tables'
  std::size_t first, last;  // its repeats to render in this round
};

struct ScenePlan {
  std::shared_ptr<const LobeTables> tables;  // null when no backend samples lobes
  double tableSeconds = 0;                   // building them: setup of the cells that use them
  // The serving tables that enough first hits take to deserve a bank, and
  // what was said about the others.
  std::vector<const Target *> lobeTargets;
  std::string lobeNote;
  std::vector<PlannedCell> cells;  // spp by spp (a round's cells cost about the same)
};

// A cell to plan: a backend word at a spp, and the repeats to render.
struct CellRequest {
  std::string word;
  std::size_t spp = 0, first = 0, last = 0;
};

// Rank 0's requests, on every rank.
std::vector<CellRequest> broadcastRequests(const Ranks &ranks, std::vector<CellRequest> requests) {
  ByteWriter w;
  w.put(std::uint64_t(requests.size()));
  for (const CellRequest &r : requests) w.put(r.word).put(r.spp).put(r.first).put(r.last);
  const std::string bytes = ranks.broadcast(ranks.root() ? w.take() : std::string());
  ByteReader r(bytes);
  requests.resize(r.get<std::uint64_t>());
  for (CellRequest &c : requests) {
    r.get(c.word);
    r.get(c.spp);
    r.get(c.first);
    r.get(c.last);
  }
  return requests;
}

ScenePlan planScene(const SceneStudy &scene, const std::vector<CellRequest> &requests,
                    const RenderStudySettings &s) {
  ScenePlan plan;
  const bool lobeIntegrator = scene.settings.integrator != IntegratorKind::Light;
  for (const CellRequest &r : requests) {
    BackendWord backend = parseBackendWord(r.word);
    const bool lobes = lobeIntegrator && backend.samplesLobes();
    plan.cells.push_back({std::move(backend), r.spp, {}, lobes, r.first, r.last});
  }
  // The lobe tables, built once before any cell (the renders then reuse
  // them through the scene's cache).
  if (std::any_of(plan.cells.begin(), plan.cells.end(),
                  [](const PlannedCell &c) { return c.samplesLobes; })) {
    const auto start = Clock::now();
    plan.tables = scene.loaded.scene.lobeTables->get(scene.loaded.scene.materials,
                                                     lobeTablesFor(scene.settings));
    if (std::any_of(plan.cells.begin(), plan.cells.end(),
                    [](const PlannedCell &c) { return c.backend.makesLobeSets(); })) {
      VisitedBins bins = visitedBins(scene.loaded.scene, scene.settings, *plan.tables, scene.slug);
      plan.lobeTargets = std::move(bins.targets);
      plan.lobeNote = std::move(bins.note);
    }
    plan.tableSeconds = secondsSince(start);
  }
  for (PlannedCell &c : plan.cells)
    c.plan =
        planBackend(c.backend, scene.settings.integrator,
                    sampledLight(scene.loaded.scene, scene.settings.integrator), plan.tables.get(),
                    plan.lobeTargets, scene.slug, c.spp, s.sets, s.seed, s.spp);
  return plan;
}

// Every set the cells need, each optimized once, on one rank; returns the
// files made now (a file found made costs its cells no setup).
std::set<fs::path> makeSceneSets(const Ranks &ranks, const SceneStudy &scene, const ScenePlan &plan,
                                 const StudyProgress &progress) {
  std::vector<SetsJob> jobs;
  for (const PlannedCell &c : plan.cells)
    jobs.insert(jobs.end(), c.plan.sets.begin(), c.plan.sets.end());
  std::set<fs::path> made;
  for (const SetsJob &madeJob : makeMissingSets(
           ranks, jobs,
           [&](std::size_t done, std::size_t total, const SetsJob &job, int e, int n, double loss) {
             if (progress)
               progress(scene.slug + ": optimize sets",
                        (double(done) + double(ranks.size()) * double(e) / n) / double(total),
                        job.label + ": loss " + formatNumber(loss));
           }))
    made.insert(madeJob.file);
  return made;
}

// The cells' repeats, interleaved: every cell's first repeat of the round,
// then every cell's second, ..., so that other work on the machine, which
// comes and goes, falls on every row alike rather than on the rows rendered
// while it ran. Rank 0 keeps the records in `repeats`, writes repeat 0's
// images and the mean spectrum of the round holding it, and puts each
// cell's row (made from all its records so far) into the table after each
// of its repeats, or notes why a cell was skipped. Returns the seconds the
// round's repeats took.
double renderCells(const Ranks &ranks, const SceneStudy &scene, const ScenePlan &plan,
                   const std::set<fs::path> &madeNow, const Image &reference,
                   const RenderStudySettings &s, CsvTable &table, CsvTable &repeats,
                   const CsvTable &refs, RenderStudyResult &result, const StudyProgress &progress) {
  struct Piece {
    std::size_t cell, repeat;
  };
  std::vector<Piece> pieces;
  std::size_t longest = 0;
  double totalWork = 0, work = 0, seconds = 0;
  for (const PlannedCell &c : plan.cells) {
    longest = std::max(longest, c.last - c.first);
    totalWork += double(c.spp) * double(c.last - c.first);
  }
  for (std::size_t k = 0; k < longest; ++k)
    for (std::size_t i = 0; i < plan.cells.size(); ++i)
      if (plan.cells[i].first + k < plan.cells[i].last)
        pieces.push_back({i, plan.cells[i].first + k});
  // Per cell: refused (its later repeats are not tried), and the sum of its
  // spectra in the round holding repeat 0 (repeats 0 .. the latest).
  std::vector<char> refused(plan.cells.size(), 0);
  std::vector<std::vector<double>> spectrumSum(plan.cells.size());
  runInRounds(
      ranks, pieces.size(),
      [&](std::size_t p) {
        const PlannedCell &c = plan.cells[pieces[p].cell];
        if (!c.plan.spec) return CellOutcome::skipped(c.plan.why).bytes();
        if (refused[pieces[p].cell]) return CellOutcome::skipped("").bytes();
        double setupSeconds = c.samplesLobes ? plan.tableSeconds : 0;
        for (const SetsJob &job : c.plan.sets)
          if (madeNow.contains(job.file))
            setupSeconds += optimizedSets(*job.target, job.request, job.file).seconds;
        RenderSettings settings = scene.settings;
        settings.spp = c.spp;
        const Cell cell{scene.loaded.scene, settings,     scene.slug, c.backend.word,
                        *c.plan.spec,       setupSeconds, reference,  scene.dir};
        const std::size_t r = pieces[p].repeat;
        return renderRepeat(cell, s, r, c.first == 0,
                            [&](std::size_t d, std::size_t n) {
                              if (progress && ranks.root())
                                progress(scene.slug + ": renders",
                                         (work + double(ranks.size()) * double(c.spp) * double(d) /
                                                     double(n)) /
                                             totalWork,
                                         c.backend.word + " spp " + std::to_string(c.spp) +
                                             ", repeat " + std::to_string(r + 1));
                            })
            .bytes();
      },
      [&](std::size_t p, const std::string &bytes) {
        const std::size_t i = pieces[p].cell, repeat = pieces[p].repeat;
        const PlannedCell &c = plan.cells[i];
        work += double(c.spp);
        if (refused[i]) return;
        const CellOutcome outcome = CellOutcome::from(bytes);
        if (!outcome.note.empty() &&
            std::find(result.notes.begin(), result.notes.end(), outcome.note) == result.notes.end())
          result.notes.push_back(outcome.note);
        if (outcome.records.empty()) {
          refused[i] = 1;
          result.skipped.push_back(scene.slug + " " + c.backend.word + " " + std::to_string(c.spp) +
                                   ": " + outcome.refusal);
          return;
        }
        const CellFiles files(scene.dir, c.backend.word, c.spp);
        if (repeat == 0) {
          writeRender(files.image.string(), outcome.image, outcome.attributes);
          writeImage(files.errorMap.string(), errorMap(outcome.image, reference));
          // Repeat 0's HDR-FLIP map, which the report shows beside the error map.
          if (!outcome.flipMap.pixels.empty()) writeImage(files.flipMap.string(), outcome.flipMap);
        }
        if (!outcome.spectrum.empty()) {
          // The mean so far, written after each repeat (a run cut short
          // leaves the mean of the repeats it rendered).
          std::vector<double> &sum = spectrumSum[i];
          sum.resize(outcome.spectrum.size());
          for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += outcome.spectrum[k];
          const double n = double(repeat + 1);
          std::vector<double> mean(sum.size());
          for (std::size_t k = 0; k < sum.size(); ++k) mean[k] = sum[k] / n;
          writeSpectrum(files.spectrum, mean);
        }
        const RepeatRecord &r = outcome.records.front();
        seconds += r.seconds;
        repeats.putRow(
            {c.backend.word, std::to_string(c.spp), std::to_string(repeat),
             std::to_string(s.seed + repeat), formatNumber(r.mse), formatNumber(r.relmse),
             formatNumber(r.screen), formatNumber(r.winsorized), formatNumber(r.topShare),
             formatNumber(r.seconds), formatNumber(r.madeSeconds), formatNumber(r.setupSeconds),
             formatNumber(r.raysPerSecond), std::to_string(r.nonFinite), std::to_string(r.rejected),
             formatNumber(r.flip)},
            3);
        const std::vector<RepeatRecord> all = cellRecords(repeats, c.backend.word, c.spp);
        table.putRow(composeRow(scene.slug, c.backend.word, c.spp, all, files, s.out), 3);
        fillDerivedColumns(table, refs, s.amortize);
      });
  return seconds;
}

// The stop of every row of the scene (and its table's columns): precision
// or budget as `plan` says; without a target, fixed for the rows that have
// no stop yet (a rerun without one keeps what an earlier target decided).
void markStops(CsvTable &table, const RepeatPlan *plan, const std::vector<std::size_t> &sceneRows) {
  const std::size_t stopped = table.column("stopped_on"),
                    worst = table.column("worst_relative_stderr");
  std::vector<std::string> stops, errors;
  for (const auto &row : table.rows()) {
    stops.push_back(row[stopped]);
    errors.push_back(row[worst]);
  }
  for (std::size_t k = 0; k < sceneRows.size(); ++k) {
    const std::size_t i = sceneRows[k];
    if (!plan && !stops[i].empty()) continue;
    stops[i] = stopName(!plan              ? RepeatStop::Fixed
                        : plan->decided[k] ? RepeatStop::Precision
                                           : RepeatStop::Budget);
    errors[i] = plan ? formatNumber(plan->worstStderr[k]) : "";
  }
  table.setColumn("stopped_on", stops);
  table.setColumn("worst_relative_stderr", errors);
}

// The scene's rows in the table, and their repeats.
std::vector<std::size_t> sceneRows(const CsvTable &table, const std::string &sceneSlug) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < table.rows().size(); ++i)
    if (table.rows()[i][table.column("scene")] == sceneSlug) out.push_back(i);
  return out;
}

// Rounds of repeats until every ratio of the scene's rows is within the
// target or the budget is spent (adaptive_repeats.h); rank 0 decides each
// round and every rank renders it. Marks each row's stop.
void addRepeats(const Ranks &ranks, const SceneStudy &scene, const RenderStudySettings &s,
                CsvTable &table, CsvTable &repeats, const Image &reference, const CsvTable &refs,
                RenderStudyResult &result, const StudyProgress &progress) {
  const bool adaptive = s.budget.targetStderr > 0;
  double spent = 0;
  for (;;) {
    std::vector<CellRequest> more;
    std::vector<std::size_t> rows;
    RepeatPlan decision;
    if (ranks.root()) {
      rows = sceneRows(table, scene.slug);
      const std::vector<TimedRow> all = timedRows(table);
      std::vector<TimedRow> timed;
      std::vector<std::size_t> counts;
      for (const std::size_t i : rows) {
        timed.push_back(all[i]);
        counts.push_back(std::size_t(parseNumber(table.rows()[i][table.column("repeats")])));
      }
      decision = planRepeats(timed, counts, s.budget);
      double predicted = 0;
      for (std::size_t k = 0; k < rows.size(); ++k) {
        if (decision.want[k] <= counts[k]) continue;
        // A row of an earlier version has no records to add to.
        if (cellRecords(repeats, timed[k].backend, timed[k].spp).size() != counts[k]) continue;
        more.push_back({timed[k].backend, timed[k].spp, counts[k], decision.want[k]});
        predicted += double(decision.want[k] - counts[k]) * timed[k].seconds;
      }
      // A round that would overrun the seconds is not started.
      if (s.budget.seconds > 0 && spent + predicted > s.budget.seconds) more.clear();
      markStops(table, adaptive ? &decision : nullptr, rows);
    }
    if (!adaptive) return;
    more = broadcastRequests(ranks, std::move(more));
    if (more.empty()) return;
    const ScenePlan plan = planScene(scene, more, s);
    const std::set<fs::path> madeNow = makeSceneSets(ranks, scene, plan, progress);
    spent += renderCells(ranks, scene, plan, madeNow, reference, s, table, repeats, refs, result,
                         progress);
  }
}

}  // namespace

RenderStudyResult runRenderStudy(const RenderStudySettings &s, const StudyProgress &progress) {
  s.validate();
  const Ranks &ranks = Ranks::world();
  if (ranks.root()) claimOutputFolder(s.out, kStudyFolder);
  RenderStudyResult result;
  result.csv = s.out / "render.csv";
  CsvTable table(result.csv, renderStudyColumns(), renderStudyDerivedColumns());
  table.loadExisting();
  table.requireOptions(s.rowOptions(), ranks.root());
  // The noise columns load empty from an older file, whose references are
  // then refused with the reason (reference_render.h), not its header.
  CsvTable refs(s.out / "references.csv", referenceColumns(), referenceOptionalColumns());
  refs.loadExisting();

  // Every rank has read the CSV before rank 0 first adds to it.
  ranks.barrier();

  const std::string assets = resolveAssetRoot(s.assets);
  for (const std::string &scenePath : s.scenes) {
    SceneStudy scene{loadScene(scenePath, assets, s.choices), {}, slug(scenePath), {}};
    scene.settings = s.render.appliedTo(scene.loaded.settings);
    scene.dir = s.out / scene.slug;

    const ReferenceSettings refSettings = referenceFor(s, scene.settings);
    const CachedReference ref = cachedReference(
        scene.loaded.scene, scene.slug, refSettings,
        s.referenceCacheDir.empty() ? ReferenceCache::fromEnvironment()
                                    : ReferenceCache(s.referenceCacheDir),
        [&](const ReferenceProgress &p) {
          if (progress) progress(scene.slug + ": reference", p.fraction, referenceProgressText(p));
        },
        s.referenceStopAfter);
    if (!ref.result.complete) {
      result.referencesIncomplete.push_back(scene.slug);
      continue;
    }
    if (ref.found) result.referencesFound.push_back(scene.slug + ": " + ref.dir.string());
    if (ranks.root()) {
      placeReference(ref, scene.dir);
      putReferenceRow(refs, scene.slug, refSettings, ref,
                      fs::relative(scene.dir / "reference.exr", s.out));
    }

    CsvTable repeats(scene.dir / "repeats.csv", repeatColumns(), repeatDerivedColumns());
    std::vector<CellRequest> missing;
    if (ranks.root()) {
      repeats.loadExisting();
      for (std::size_t spp : s.spp)
        for (const std::string &word : s.backends) missing.push_back({word, spp, 0, s.repeats});
      // A row a run cut short left with fewer repeats than asked is topped
      // up from its records (a row of an earlier version has none to add
      // to, and is kept).
      std::erase_if(missing, [&](CellRequest &r) {
        const auto row = table.findRow({scene.slug, r.word, std::to_string(r.spp)});
        if (!row) return false;
        r.first = cellRecords(repeats, r.word, r.spp).size();
        const auto count = std::size_t(parseNumber((*row)[table.column("repeats")]));
        return r.first < count || r.first >= r.last;
      });
    }
    missing = broadcastRequests(ranks, std::move(missing));
    const ScenePlan plan = planScene(scene, missing, s);
    if (!plan.lobeNote.empty()) result.notes.push_back(plan.lobeNote);
    const std::set<fs::path> madeNow = makeSceneSets(ranks, scene, plan, progress);
    renderCells(ranks, scene, plan, madeNow, ref.result.image, s, table, repeats, refs, result,
                progress);
    addRepeats(ranks, scene, s, table, repeats, ref.result.image, refs, result, progress);
    ranks.barrier();
  }
  // Rows kept from an earlier run take this run's K and references too.
  if (ranks.root() && !table.rows().empty()) {
    fillDerivedColumns(table, refs, s.amortize);
    // The convergence rates of every row with three or more spp values,
    // made again from the whole table.
    if (const auto slopes = slopeRows(table); !slopes.empty()) {
      CsvTable out(s.out / "slopes.csv", slopeColumns());
      for (const auto &row : slopes) out.addRow(row);
    }
  }
  return result;
}

}  // namespace nuld::study
