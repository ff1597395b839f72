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
#include "tools/study/baselines.h"
#include "tools/study/csv_table.h"
#include "tools/study/equal_time.h"
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
// again after the old one was refused).
void putReferenceRow(CsvTable &refs, const std::string &scene, const ReferenceSettings &r,
                     const ReferenceResult &result, const fs::path &image) {
  refs.putRow(
      {scene, r.backend, std::to_string(r.totalSpp()),
       std::to_string(r.render.width) + "x" + std::to_string(r.render.height),
       toString(r.render.integrator), formatNumber(result.noise.variance),
       formatNumber(result.noise.relVariance), formatNumber(result.totalSeconds), image.string()},
      1);
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

// Where a cell's first render and its error map go.
struct CellFiles {
  fs::path image, errorMap, spectrum;
  CellFiles(const fs::path &dir, const std::string &backend, std::size_t spp) {
    const std::string stem = slug(backend) + "_spp" + std::to_string(spp);
    image = dir / (stem + ".exr");
    errorMap = dir / (stem + "_error.png");
    spectrum = dir / (stem + "_spectrum.csv");
  }
};

// The repeats' mean radially averaged power spectrum of the error
// (errorPowerSpectrum) as CSV: radius, frequency in cycles per pixel, power.
void writeSpectrum(const fs::path &file, const std::vector<double> &power) {
  std::string text = "radius,cycles_per_pixel,power\n";
  const double side = 2.0 * double(power.size() - 1);
  for (std::size_t r = 0; r < power.size(); ++r)
    text += std::to_string(r) + "," + formatNumber(double(r) / side) + "," +
            formatNumber(power[r]) + "\n";
  writeFileAtomically(file, text);
}

// One cell of the table: `repeats` renders of one backend at one spp,
// scored against the reference.
struct Cell {
  const Scene &scene;
  RenderSettings settings;  // spp set
  std::string sceneSlug, backend;
  BackendSpec spec;
  double setupSeconds = 0;
  const Image &reference;
  fs::path dir;

  CellFiles files() const { return {dir, backend, settings.spp}; }
};

// What a cell sends to rank 0: its row, or why it has none (the backend's
// refusal, or the scene's lack of what the backend needs), and its first
// render (written beside the reference with its error map).
struct CellOutcome {
  std::vector<std::string> row;  // empty when refused
  std::string refusal;
  std::string note;              // what the backend decided that a user should hear (its note())
  std::vector<double> spectrum;  // the repeats' mean errorPowerSpectrum
  Image image;
  ImageAttributes attributes;

  // A cell the scene cannot serve (no map, no Disney material): no row.
  static CellOutcome skipped(const std::string &why) {
    CellOutcome c;
    c.refusal = why;
    return c;
  }
  std::string bytes() const {
    return ByteWriter()
        .put(row)
        .put(refusal)
        .put(note)
        .put(spectrum)
        .put(image)
        .put(attributes)
        .take();
  }
  static CellOutcome from(std::string_view bytes) {
    ByteReader r(bytes);
    CellOutcome c;
    r.get(c.row);
    r.get(c.refusal);
    r.get(c.note);
    r.get(c.spectrum);
    r.get(c.image);
    r.get(c.attributes);
    return c;
  }
};

// The cell's outcome; a refusal (BackendRefusal) is an outcome, any other
// error propagates. `progress(r, d, n)` follows repeat r's render.
CellOutcome renderCell(
    const Cell &c, const RenderStudySettings &s,
    const std::function<void(std::size_t r, std::size_t d, std::size_t n)> &progress) {
  CellOutcome out;
  std::vector<double> mse, relmse, screen, whole, made, raysPerSecond;
  std::size_t nonFinite = 0;
  std::uint64_t rejected = 0;
  for (std::size_t r = 0; r < s.repeats; ++r) {
    const auto start = Clock::now();
    const auto b = makeBackend(c.spec, s.seed + r);
    RenderStats stats;
    Image img;
    try {
      img = render(c.scene, c.settings, *b, &stats,
                   [&](std::size_t d, std::size_t n) { progress(r, d, n); });
    } catch (const BackendRefusal &e) {
      out.refusal = e.what();
      return out;
    }
    whole.push_back(secondsSince(start));
    made.push_back(stats.setsMadeSeconds);
    raysPerSecond.push_back(stats.raysPerSecond());
    const ImageError e = compareImages(img, c.reference);
    mse.push_back(e.mse);
    relmse.push_back(e.relmse);
    screen.push_back(e.screen);
    const std::vector<double> spectrum = errorPowerSpectrum(img, c.reference);
    out.spectrum.resize(spectrum.size());
    for (std::size_t k = 0; k < spectrum.size(); ++k)
      out.spectrum[k] += spectrum[k] / double(s.repeats);
    nonFinite += e.nonFinitePixels;
    rejected += stats.rejectedSamples;
    if (r == 0) {
      out.attributes = renderAttributes(c.sceneSlug, c.scene, c.settings, b->name(), s.seed, stats);
      out.image = std::move(img);
      out.note = b->report().note;
    }
  }
  // Banks a backend made in its first repeat (neural) are setup, not render
  // time (splitRepeatSeconds).
  const RepeatSeconds split = splitRepeatSeconds(whole, made);
  const MeanAndError m = meanAndError(mse), rm = meanAndError(relmse),
                     t = meanAndError(split.render), rps = meanAndError(raysPerSecond);
  out.row = {c.sceneSlug,
             c.backend,
             std::to_string(c.settings.spp),
             std::to_string(s.repeats),
             formatNumber(m.mean),
             formatNumber(m.stderr_),
             formatNumber(rm.mean),
             formatNumber(rm.stderr_),
             formatNumber(t.mean),
             formatNumber(c.setupSeconds + split.setup),
             "",  // total_seconds .. amortize: fillEqualTime, over the whole table
             "",
             "",
             "",
             formatNumber(rps.mean),
             std::to_string(nonFinite),
             std::to_string(rejected),
             fs::relative(c.files().image, s.out).string(),
             fs::relative(c.files().errorMap, s.out).string()};
  out.row.resize(renderStudyColumns().size());  // baselineColumns: fillBaselineColumns
  const MeanAndError sm = meanAndError(screen);
  const auto at = [](const std::string &name) {
    const auto &c = renderStudyColumns();
    return std::size_t(std::find(c.begin(), c.end(), name) - c.begin());
  };
  out.row[at(screenColumns()[0])] = formatNumber(sm.mean);
  out.row[at(screenColumns()[1])] = formatNumber(sm.stderr_);
  return out;
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
  bool samplesLobes;  // its setup includes the lobe tables'
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

ScenePlan planScene(const SceneStudy &scene, const CsvTable &table, const RenderStudySettings &s) {
  ScenePlan plan;
  const bool lobeIntegrator = scene.settings.integrator != IntegratorKind::Light;
  for (std::size_t spp : s.spp)
    for (const std::string &word : s.backends)
      if (!table.hasRow({scene.slug, word, std::to_string(spp)})) {
        BackendWord backend = parseBackendWord(word);
        const bool lobes = lobeIntegrator && backend.samplesLobes();
        plan.cells.push_back({std::move(backend), spp, {}, lobes});
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

// The cells, rendered side by side; rank 0 writes their images and adds
// their rows in cell order, or notes why a cell was skipped.
void renderCells(const Ranks &ranks, const SceneStudy &scene, const ScenePlan &plan,
                 const std::set<fs::path> &madeNow, const Image &reference,
                 const RenderStudySettings &s, CsvTable &table, const CsvTable &refs,
                 RenderStudyResult &result, const StudyProgress &progress) {
  double totalWork = 0, work = 0;
  for (const PlannedCell &c : plan.cells) totalWork += double(c.spp) * double(s.repeats);
  runInRounds(
      ranks, plan.cells.size(),
      [&](std::size_t i) {
        const PlannedCell &c = plan.cells[i];
        if (!c.plan.spec) return CellOutcome::skipped(c.plan.why).bytes();
        double setupSeconds = c.samplesLobes ? plan.tableSeconds : 0;
        for (const SetsJob &job : c.plan.sets)
          if (madeNow.contains(job.file))
            setupSeconds += optimizedSets(*job.target, job.request, job.file).seconds;
        RenderSettings settings = scene.settings;
        settings.spp = c.spp;
        const Cell cell{scene.loaded.scene, settings,     scene.slug, c.backend.word,
                        *c.plan.spec,       setupSeconds, reference,  scene.dir};
        const double cellWork = double(c.spp) * double(s.repeats);
        return renderCell(cell, s,
                          [&](std::size_t r, std::size_t d, std::size_t n) {
                            if (progress && ranks.root())
                              progress(scene.slug + ": renders",
                                       (work + double(ranks.size()) * cellWork / double(s.repeats) *
                                                   (double(r) + double(d) / double(n))) /
                                           totalWork,
                                       c.backend.word + " spp " + std::to_string(c.spp));
                          })
            .bytes();
      },
      [&](std::size_t i, const std::string &bytes) {
        const PlannedCell &c = plan.cells[i];
        work += double(c.spp) * double(s.repeats);
        const CellOutcome outcome = CellOutcome::from(bytes);
        if (!outcome.note.empty() &&
            std::find(result.notes.begin(), result.notes.end(), outcome.note) == result.notes.end())
          result.notes.push_back(outcome.note);
        if (outcome.row.empty()) {
          result.skipped.push_back(scene.slug + " " + c.backend.word + " " + std::to_string(c.spp) +
                                   ": " + outcome.refusal);
          return;
        }
        const CellFiles files(scene.dir, c.backend.word, c.spp);
        writeRender(files.image.string(), outcome.image, outcome.attributes);
        writeImage(files.errorMap.string(), errorMap(outcome.image, reference));
        if (!outcome.spectrum.empty()) writeSpectrum(files.spectrum, outcome.spectrum);
        table.addRow(outcome.row);
        fillDerivedColumns(table, refs, s.amortize);
      });
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
  CsvTable refs(s.out / "references.csv", referenceColumns(), {"variance", "relvariance"});
  refs.loadExisting();

  // Every rank has read the CSV before rank 0 first adds to it.
  ranks.barrier();

  const std::string assets = resolveAssetRoot(s.assets);
  for (const std::string &scenePath : s.scenes) {
    SceneStudy scene{loadScene(scenePath, assets, s.choices), {}, slug(scenePath), {}};
    scene.settings = s.render.appliedTo(scene.loaded.settings);
    scene.dir = s.out / scene.slug;

    const ReferenceSettings refSettings = referenceFor(s, scene.settings);
    const ReferenceResult ref = renderReference(
        scene.loaded.scene, sceneIdentity(scenePath), refSettings, scene.dir,
        [&](const ReferenceProgress &p) {
          if (progress)
            progress(scene.slug + ": reference", p.fraction,
                     "pass " + std::to_string(p.passesDone) + "/" + std::to_string(p.passes));
        },
        s.referenceStopAfter);
    if (!ref.complete) {
      result.referencesIncomplete.push_back(scene.slug);
      continue;
    }
    if (ranks.root())
      putReferenceRow(refs, scene.slug, refSettings, ref,
                      fs::relative(scene.dir / "reference.exr", s.out));

    const ScenePlan plan = planScene(scene, table, s);
    if (!plan.lobeNote.empty()) result.notes.push_back(plan.lobeNote);
    const std::set<fs::path> madeNow = makeSceneSets(ranks, scene, plan, progress);
    renderCells(ranks, scene, plan, madeNow, ref.image, s, table, refs, result, progress);
    ranks.barrier();
  }
  // Rows kept from an earlier run take this run's K and references too.
  if (ranks.root() && !table.rows().empty()) fillDerivedColumns(table, refs, s.amortize);
  return result;
}

}  // namespace nuld::study
