#include "tools/study/render_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "renderer/image_metrics.h"
#include "renderer/lobe_tables.h"
#include "renderer/sampler_backend.h"
#include "sampler/io/image_io.h"
#include "sampler/targets/target_spec.h"
#include "scenes/scene_file.h"
#include "tools/study/csv_table.h"
#include "tools/study/optimized_sets.h"
#include "tools/study/stopwatch.h"

namespace nuld::study {

namespace fs = std::filesystem;

namespace {

// A study backend may carry the suffix "+shift": its non-uniform sets are
// then randomized in primary space (the renderer's shifted:PATHS).
constexpr std::string_view kShiftSuffix = "+shift";
bool hasShiftSuffix(const std::string &b) {
  return b.size() > kShiftSuffix.size() && b.ends_with(kShiftSuffix);
}
std::string withoutShift(const std::string &b) {
  return hasShiftSuffix(b) ? b.substr(0, b.size() - kShiftSuffix.size()) : b;
}

bool isStudyBackend(const std::string &b) {
  const std::string base = withoutShift(b);
  const auto &study = studyBackendDescriptions();
  return std::any_of(study.begin(), study.end(),
                     [&](const BackendDescription &d) { return base == d.spelling; });
}

// Mean and standard error of the mean.
struct Summary {
  double mean = 0, stderr_ = 0;
};
Summary summarize(const std::vector<double> &v) {
  Summary s;
  for (double x : v) s.mean += x / double(v.size());
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.stderr_ = std::sqrt(ss / double(v.size() - 1) / double(v.size()));
  }
  return s;
}

// The renderer backend spec for a study backend at one spp, making the
// optimized sets first when the study owns them. Returns "" when the scene
// cannot use the backend (reason in `why`).
struct ResolvedBackend {
  std::string spec;
  double setupSeconds = 0;
  std::string why;
};

// Optimized sets for one target, from the study's cache or made now.
OptimizedSets setsFor(const Target &target, const OptimizedSetsRequest &request,
                      const fs::path &file, const std::string &task,
                      const StudyProgress &progress) {
  return optimizedSets(target, request, file, [&](int e, int n, double loss) {
    if (progress) progress(task, double(e) / n, "loss " + formatNumber(loss));
  });
}

ResolvedBackend resolveBackend(const std::string &backend, const Scene &scene,
                               const RenderSettings &render, const std::string &sceneSlug,
                               std::size_t spp, const RenderStudySettings &s,
                               const StudyProgress &progress) {
  if (!isStudyBackend(backend)) return {backend, 0, ""};
  if (hasShiftSuffix(backend)) {
    ResolvedBackend r =
        resolveBackend(withoutShift(backend), scene, render, sceneSlug, spp, s, progress);
    if (r.spec.rfind("optimized:", 0) == 0) r.spec = "shifted:" + r.spec.substr(10);
    return r;
  }
  OptimizedSetsRequest request;
  request.n = spp;
  request.instances = s.optimizedInstances;
  request.epochs = s.optimizedEpochs;
  request.seed = s.seed;
  const std::string task = sceneSlug + ": " + backend + " N=" + std::to_string(spp);
  const fs::path cache = s.out / "cache";
  std::vector<std::string> paths;
  double seconds = 0;

  if (backend == "optimized-uniform") {
    // Sets for the periodic L2 discrepancy: a Cranley-Patterson shift, which
    // the backend applies per pixel and pair, leaves it unchanged, so every
    // shifted set is as good as the optimized one (sets for the plain L2
    // discrepancy lose their quality under the shift).
    const auto uniform = makeTarget("uniform");
    request.objective = Objective::PeriodicL2;
    const OptimizedSets sets = setsFor(
        *uniform, request, cachedSetsPath(cache, *uniform, optimizerSettings(*uniform, request)),
        task, progress);
    return {"optimized:" + sets.file.string(), sets.seconds, ""};
  }
  if (backend == "optimized" || backend == "optimized-both") {
    if (!scene.environment || !scene.environment->target())
      return {"", 0, "the scene has no (non-black) environment map to optimize for"};
    const OptimizedSets sets =
        setsFor(*scene.environment->target(), request,
                cache / (sceneSlug + "_envmap_n" + std::to_string(spp) + ".ptsb"), task, progress);
    paths.push_back(sets.file.string());
    seconds += sets.seconds;
  }
  if (backend == "optimized-bsdf" || backend == "optimized-both") {
    // A bank per lobe table the renderer will build for this scene (the same
    // settings give the same specs), optimized for the exact L2asd
    // objective: as good as the sphere preset's soft boxes for these targets
    // at 1/30 to 1/100 of the time (tools/experiments/lobe_banks_log.md).
    const LobeTables tables(scene.materials, lobeTablesFor(render));
    if (tables.materials() == 0)
      return {"", 0, "the scene has no Disney material to optimize lobe sets for"};
    request.objective = Objective::ExactL2asd;
    request.unionWeight = s.lobeUnionWeight;
    const auto targets = tables.targets();
    // The directory is the bank the renderer loads whole, so its name carries
    // the settings: sets made with other settings never join it.
    char hash[17];
    std::snprintf(hash, sizeof hash, "%08llx",
                  static_cast<unsigned long long>(
                      hashString(optimizerSettings(*targets[0], request).describe()) >> 32));
    const fs::path dir = cache / (sceneSlug + "_lobes_n" + std::to_string(spp) + "_" + hash);
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const OptimizedSets sets = setsFor(
          *targets[k], request,
          cachedSetsPath(dir, *targets[k], optimizerSettings(*targets[k], request)),
          task + " lobe " + std::to_string(k + 1) + "/" + std::to_string(targets.size()), progress);
      seconds += sets.seconds;
    }
    paths.push_back(dir.string());
  }
  std::string spec = "optimized:";
  for (std::size_t i = 0; i < paths.size(); ++i) spec += (i ? "," : "") + paths[i];
  return {spec, seconds, ""};
}

ReferenceSettings referenceFor(const RenderStudySettings &s, const RenderSettings &render) {
  ReferenceSettings r = s.reference;
  r.render = render;
  return r;
}

void appendReferenceRow(CsvTable &refs, const std::string &scene, const ReferenceSettings &r,
                        const ReferenceResult &result, const fs::path &image) {
  if (refs.hasRow({scene})) return;
  refs.addRow({scene, r.backend, std::to_string(r.totalSpp()),
               std::to_string(r.render.width) + "x" + std::to_string(r.render.height),
               toString(r.render.integrator), formatNumber(result.totalSeconds), image.string()});
}

// One cell of the table: `repeats` renders of one backend at one spp,
// scored against the reference. The first render and its error map are
// written beside the reference.
struct Cell {
  const Scene &scene;
  RenderSettings settings;  // spp set
  std::string sceneSlug, backend;
  const ResolvedBackend &resolved;
  const Image &reference;
  fs::path dir;
};

// The cell's row, or nullopt with `refusal` set when the backend refused the
// render (BackendRefusal); any other error propagates. `progress(d, n)`
// follows repeat r's render.
std::optional<std::vector<std::string>> renderCell(
    const Cell &c, const RenderStudySettings &s, std::string &refusal,
    const std::function<void(std::size_t r, std::size_t d, std::size_t n)> &progress) {
  const std::string stem = slug(c.backend) + "_spp" + std::to_string(c.settings.spp);
  const fs::path image = c.dir / (stem + ".exr"), errorPath = c.dir / (stem + "_error.png");
  std::vector<double> mse, relmse, seconds, raysPerSecond;
  std::size_t nonFinite = 0;
  std::uint64_t rejected = 0;
  for (std::size_t r = 0; r < s.repeats; ++r) {
    const auto start = Clock::now();
    const auto b = makeBackend(c.resolved.spec, s.seed + r);
    RenderStats stats;
    Image img;
    try {
      img = render(c.scene, c.settings, *b, &stats,
                   [&](std::size_t d, std::size_t n) { progress(r, d, n); });
    } catch (const BackendRefusal &e) {
      refusal = e.what();
      return std::nullopt;
    }
    seconds.push_back(secondsSince(start));
    raysPerSecond.push_back(stats.raysPerSecond());
    const ImageError e = compareImages(img, c.reference);
    mse.push_back(e.mse);
    relmse.push_back(e.relmse);
    nonFinite += e.nonFinitePixels;
    rejected += stats.rejectedSamples;
    if (r == 0) {
      writeRender(image.string(), img,
                  renderAttributes(c.sceneSlug, c.settings, b->name(), s.seed, stats));
      writeImage(errorPath.string(), errorMap(img, c.reference));
    }
  }
  const Summary m = summarize(mse), rm = summarize(relmse), t = summarize(seconds),
                rps = summarize(raysPerSecond);
  return std::vector<std::string>{c.sceneSlug,
                                  c.backend,
                                  std::to_string(c.settings.spp),
                                  std::to_string(s.repeats),
                                  formatNumber(m.mean),
                                  formatNumber(m.stderr_),
                                  formatNumber(rm.mean),
                                  formatNumber(rm.stderr_),
                                  formatNumber(t.mean),
                                  formatNumber(c.resolved.setupSeconds),
                                  formatNumber(rps.mean),
                                  std::to_string(nonFinite),
                                  std::to_string(rejected),
                                  fs::relative(image, s.out).string(),
                                  fs::relative(errorPath, s.out).string()};
}

}  // namespace

const std::vector<BackendDescription> &studyBackendDescriptions() {
  static const std::vector<BackendDescription> list{
      {"optimized", "sets optimized for the scene's environment map (light samples)"},
      {"optimized-uniform", "uniform sets for the periodic L2 discrepancy (primary samples)"},
      {"optimized-bsdf", "lobe banks for the scene's Disney materials (BSDF samples)"},
      {"optimized-both", "optimized and optimized-bsdf together"},
  };
  return list;
}

const std::vector<std::string> &renderStudyColumns() {
  static const std::vector<std::string> columns{"scene",
                                                "backend",
                                                "spp",
                                                "repeats",
                                                "mse",
                                                "mse_stderr",
                                                "relmse",
                                                "relmse_stderr",
                                                "seconds",
                                                "setup_seconds",
                                                "rays_per_second",
                                                "nonfinite_pixels",
                                                "rejected_samples",
                                                "image",
                                                "error_map"};
  return columns;
}

void RenderStudySettings::validate() const {
  if (scenes.empty()) throw std::invalid_argument("study render: no scene given");
  if (backends.empty()) throw std::invalid_argument("--backends: no backend given");
  if (spp.empty()) throw std::invalid_argument("--spp: no sample count given");
  for (std::size_t n : spp)
    if (n == 0) throw std::invalid_argument("--spp: counts must be positive");
  if (!(resolutionScale > 0 && resolutionScale <= 16))
    throw std::invalid_argument("--res-scale: expected a factor in (0, 16]");
  if (repeats == 0) throw std::invalid_argument("--repeats: must be at least 1");
  if (optimizedInstances == 0) throw std::invalid_argument("--opt-instances: must be at least 1");
  if (!(lobeUnionWeight >= 0) || !std::isfinite(lobeUnionWeight))
    throw std::invalid_argument("--opt-union-weight: expected a finite weight >= 0");
  if (lobeMix && !(*lobeMix >= 0 && *lobeMix <= 1))
    throw std::invalid_argument("--lobe-mix: expected a number in [0, 1]");
  if (out.empty()) throw std::invalid_argument("study render: -o OUTDIR is required");
  for (const auto &b : backends)  // fail now, not after an hour of reference
    if (!isStudyBackend(b) && b.rfind("optimized:", 0) != 0 && b.rfind("points:", 0) != 0 &&
        b.rfind("neural:", 0) != 0)
      makeBackend(b, 0);
}

std::string sceneIdentity(const std::string &scenePath) {
  const std::string name = slug(scenePath);
  if (isBuiltInScene(scenePath)) return name;
  std::ifstream in(scenePath, std::ios::binary);
  if (!in) throw std::runtime_error(scenePath + ": cannot read the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(hashString(text.str())));
  return name + " scene_hash=" + hash;
}

std::string slug(const std::string &name) {
  std::string base = name;
  if (const auto colon = base.find(':'); colon != std::string::npos)
    base = base.substr(0, colon) + "-" + fs::path(base.substr(colon + 1)).stem().string();
  else if (base.find('/') != std::string::npos || base.find('.') != std::string::npos)
    base = fs::path(base).stem().string();
  for (char &c : base)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  return base;
}

RenderStudyResult runRenderStudy(const RenderStudySettings &s, const StudyProgress &progress) {
  s.validate();
  fs::create_directories(s.out);
  RenderStudyResult result;
  result.csv = s.out / "render.csv";
  CsvTable table(result.csv, renderStudyColumns());
  table.loadExisting();
  CsvTable refs(s.out / "references.csv",
                {"scene", "backend", "spp", "resolution", "integrator", "seconds", "image"});
  refs.loadExisting();

  const std::string assets = resolveAssetRoot(s.assets);
  for (const std::string &scenePath : s.scenes) {
    LoadedScene loaded = loadScene(scenePath, assets);
    RenderSettings rs = loaded.settings;
    if (s.width) {
      rs.width = s.width, rs.height = s.height ? s.height : s.width;
    } else if (s.resolutionScale != 1) {
      rs.width = std::max(1, int(std::lround(rs.width * s.resolutionScale)));
      rs.height = std::max(1, int(std::lround(rs.height * s.resolutionScale)));
    }
    if (s.integrator) rs.integrator = *s.integrator;
    if (s.maxDepth) rs.maxDepth = s.maxDepth;
    if (s.lobeMix) rs.lobeTables.samplingMix = s.lobeMix;
    const std::string sceneSlug = slug(scenePath);
    const fs::path dir = s.out / sceneSlug;

    const ReferenceSettings refSettings = referenceFor(s, rs);
    const ReferenceResult ref = renderReference(
        loaded.scene, sceneIdentity(scenePath), refSettings, dir, [&](const ReferenceProgress &p) {
          if (progress)
            progress(sceneSlug + ": reference", p.fraction,
                     "pass " + std::to_string(p.passesDone) + "/" + std::to_string(p.passes));
        });
    appendReferenceRow(refs, sceneSlug, refSettings, ref,
                       fs::relative(dir / "reference.exr", s.out));

    // Render cost grows with spp; the progress fraction follows it.
    double totalWork = 0, work = 0;
    for (std::size_t spp : s.spp) totalWork += double(spp) * s.backends.size() * s.repeats;
    for (const std::string &backend : s.backends) {
      for (std::size_t spp : s.spp) {
        const double cellWork = double(spp) * s.repeats;
        if (table.hasRow({sceneSlug, backend, std::to_string(spp)})) {
          work += cellWork;
          continue;
        }
        const ResolvedBackend resolved =
            resolveBackend(backend, loaded.scene, rs, sceneSlug, spp, s, progress);
        if (resolved.spec.empty()) {
          result.skipped.push_back(sceneSlug + " " + backend + " " + std::to_string(spp) + ": " +
                                   resolved.why);
          work += cellWork;
          continue;
        }
        RenderSettings settings = rs;
        settings.spp = spp;
        const Cell cell{loaded.scene, settings, sceneSlug, backend, resolved, ref.image, dir};
        std::string refusal;
        const auto row =
            renderCell(cell, s, refusal, [&](std::size_t r, std::size_t d, std::size_t n) {
              if (progress)
                progress(sceneSlug + ": renders",
                         (work + cellWork / s.repeats * (double(r) + double(d) / n)) / totalWork,
                         backend + " spp " + std::to_string(spp));
            });
        work += cellWork;
        if (!row) {
          result.skipped.push_back(sceneSlug + " " + backend + " " + std::to_string(spp) + ": " +
                                   refusal);
          continue;
        }
        table.addRow(*row);
      }
    }
  }
  return result;
}

}  // namespace nuld::study
