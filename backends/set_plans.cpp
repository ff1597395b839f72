#include "backends/set_plans.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "backends/ranks.h"
#include "backends/set_cache.h"
#include "backends/stopwatch.h"
#include "renderer/path_integrator.h"
#include "renderer/render.h"
#include "sampler/enum_names.h"
#include "sampler/io/round_trip.h"
#include "sampler/targets/target_spec.h"

namespace nuld {

LobeVisits lobeTableVisits(const Scene &scene, const LobeTables &tables, int width, int height,
                           int raysPerSide) {
  const PerspectiveCamera camera(scene.camera, width, height);
  const int side = std::max(raysPerSide, 1);
  // Row by row in parallel; each row's counts merged in row order.
  std::vector<std::map<const Target *, std::size_t>> rows(std::size_t(std::max(height, 0)));
  tbb::parallel_for(0, std::max(height, 0), [&](int y) {
    auto &counts = rows[std::size_t(y)];
    for (int x = 0; x < width; ++x)
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
          const Ray ray = camera.generateRay({x + (i + 0.5) / side, y + (j + 0.5) / side});
          const auto hit = scene.geometry.intersect(ray);
          if (!hit) continue;
          const Bsdf *bsdf = scene.materials[hit->mesh].get();
          const Vec3 wo = shadingLocal(*hit, -ray.direction);
          if (const auto f = tables.frame(bsdf, wo)) ++counts[f->table];
        }
  });
  LobeVisits visits;
  visits.total = std::size_t(std::max(width, 0)) * std::size_t(std::max(height, 0)) * side * side;
  for (const auto &counts : rows)
    for (const auto &[table, n] : counts) visits.rays[table] += n;
  return visits;
}

namespace fs = std::filesystem;

namespace {

// A bank costs seconds of optimization; a bin that fewer than this share of
// camera rays' first hits take adds too little to the image's error to
// deserve one (its samples fall back to Owen-Sobol through the table).
constexpr double kMinBinShare = 1e-3;

}  // namespace

BackendPlan planBackend(const BackendWord &backend, IntegratorKind integrator,
                        const EnvironmentLight *light, const LobeTables *tables,
                        const std::vector<const Target *> &lobeTargets,
                        const std::string &sceneSlug, std::size_t spp, const SetSettings &s,
                        std::uint64_t seed, const std::vector<std::size_t> &sppFamily) {
  using Sets = BackendSets;
  if (backend.sets == Sets::None) return {backend.spec, {}, ""};
  OptimizedSetsRequest request;
  request.n = spp;
  request.instances = s.instances;
  request.epochs = s.epochs;
  request.seed = seed;
  const std::string task =
      sceneSlug + ": " + backend.word + " N=" + std::to_string(spp) + (s.nested ? " (nested)" : "");
  const SetCache cache = s.cacheDir.empty() ? SetCache::fromEnvironment() : SetCache(s.cacheDir);
  std::vector<std::string> paths;
  BackendPlan plan;
  // The sets' backend: every file and directory of `paths`, shifted in
  // primary space for a +shift word.
  const auto banks = [&] {
    std::string argument;
    for (std::size_t i = 0; i < paths.size(); ++i) argument += (i ? "," : "") + paths[i];
    return BackendSpec{backend.spec.shift ? BackendKind::Shifted : BackendKind::Optimized,
                       argument};
  };
  // The sets of one target: with --opt-nested one nested bank of the
  // largest spp whose prefixes are the other spp (or any nested bank in the
  // cache that holds at least this spp: no set to make); else a bank of spp
  // points.
  const std::size_t largest = std::max(
      spp, sppFamily.empty() ? spp : *std::max_element(sppFamily.begin(), sppFamily.end()));
  const auto addSets = [&](const Target &target, OptimizedSetsRequest r, const std::string &label) {
    if (s.nested) {
      r.n = largest;
      for (std::size_t m : sppFamily)
        if (m < largest) r.nested.push_back(m);
      std::sort(r.nested.begin(), r.nested.end());
      r.nested.erase(std::unique(r.nested.begin(), r.nested.end()), r.nested.end());
      if (const fs::path found = cache.findNested(target, optimizerSettings(target, r), spp);
          !found.empty()) {
        plan.found.push_back({&target, found});
        paths.push_back(found.string());
        return;
      }
    }
    const fs::path file = cache.entry(target, optimizerSettings(target, r));
    plan.sets.push_back({&target, r, file, label});
    paths.push_back(file.string());
  };

  if (backend.sets == Sets::Uniform) {
    // Sets for the periodic L2 discrepancy: a Cranley-Patterson shift, which
    // the backend applies per pixel and pair, leaves it unchanged, so every
    // shifted set is as good as the optimized one (sets for the plain L2
    // discrepancy lose their quality under the shift).
    static const auto uniform = makeTarget("uniform");
    request.objective = Objective::PeriodicL2;
    addSets(*uniform, request, task);
    plan.spec = banks();
    return plan;
  }
  // An integrator that draws no light (or no BSDF) sample leaves that half
  // of optimized-both out, and refuses a word that has no other half.
  const bool envSets = backend.makesEnvSets() && integrator != IntegratorKind::Bsdf;
  const bool lobeSets = backend.makesLobeSets() && integrator != IntegratorKind::Light;
  if (backend.makesEnvSets() && !envSets && !lobeSets)
    return {std::nullopt,
            {},
            "the bsdf integrator samples BSDFs only: no light sample for "
            "the map's sets to serve"};
  if (backend.makesLobeSets() && !envSets && !lobeSets)
    return {std::nullopt,
            {},
            "the light integrator samples the light only: no BSDF sample "
            "for lobe banks to serve"};
  if (envSets) {
    if (!light || !light->target())
      return {std::nullopt, {}, "the scene has no (non-black) environment map to optimize for"};
    OptimizedSetsRequest env = request;
    if (s.envObjective == Objective::ExactL2asd) env.preset = "sphere-exact";
    env.unionWeight = s.unionWeight;
    addSets(*light->target(), env, task);
  }
  if (lobeSets) {
    // A bank per lobe table the renderer will build for this scene (the same
    // settings give the same specs), optimized for the exact L2asd
    // objective: as good as the sphere preset's soft boxes for these targets
    // in a small part of the time (tools/experiments/lobe_banks_log.md).
    if (!tables || tables->materials() == 0)
      return {std::nullopt, {}, "the scene has no Disney material to optimize lobe sets for"};
    request.objective = Objective::ExactL2asd;
    request.unionWeight = s.unionWeight;
    request.epochs = s.lobeBankEpochs();
    const auto &targets = lobeTargets;  // the tabulated bins first hits take
    // No bin whose route is the table: every BSDF sample keeps the
    // material's sampler. With map sets beside, the row serves those alone;
    // without, it would be sobol's bit for bit, so it serves nothing and is
    // refused, as a study's skipped row with this reason.
    if (targets.empty()) {
      if (paths.empty())
        return {std::nullopt,
                {},
                "no BSDF sample of the scene goes through a lobe table (the lobe routes keep "
                "every material's own sampler at the bins first hits take; --lobe-routes "
                "table routes them all): there is nothing for lobe sets to serve"};
      plan.spec = banks();
      return plan;
    }
    // One entry per lobe table, each named to the backend.
    for (std::size_t k = 0; k < targets.size(); ++k)
      addSets(*targets[k], request,
              task + " lobe " + std::to_string(k + 1) + "/" + std::to_string(targets.size()));
  }
  plan.spec = banks();
  return plan;
}

VisitedBins visitedBins(const Scene &scene, const RenderSettings &settings,
                        const LobeTables &tables, const std::string &slug) {
  VisitedBins out;
  const LobeVisits visits = lobeTableVisits(scene, tables, settings.width, settings.height);
  const std::vector<const Target *> all = tables.targets();
  std::vector<const LobeBinRoute *> served;  // the routes of `all`, in order
  for (const LobeBinRoute &r : tables.routes())
    if (r.table) served.push_back(&r);
  std::string skipped;
  std::size_t unseen = 0, rare = 0;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const auto it = visits.rays.find(all[k]);
    const std::size_t rays = it == visits.rays.end() ? 0 : it->second;
    if (double(rays) >= kMinBinShare * double(visits.total)) {
      out.targets.push_back(all[k]);
      continue;
    }
    ++(rays ? rare : unseen);
    char bin[96];
    std::snprintf(bin, sizeof bin, "%smaterial %zu at %.0f/%.0f deg (%zu rays)",
                  skipped.empty() ? "" : ", ", served[k]->material, served[k]->thetaDegrees,
                  served[k]->phiDegrees, rays);
    skipped += bin;
  }
  if (unseen + rare > 0)
    out.note = slug + ": lobe banks for " + std::to_string(out.targets.size()) + " of " +
               std::to_string(all.size()) + " tabulated bins; " + std::to_string(unseen) +
               " no camera ray's first hit takes and " + std::to_string(rare) +
               " fewer than 0.1 % of " + std::to_string(visits.total) + " do (" + skipped +
               "): they sample Owen-Sobol through the table";
  return out;
}

PreparedBackend prepareBackend(const BackendWord &backend, const Scene &scene,
                               const RenderSettings &settings, const std::string &sceneName,
                               const SetSettings &sets, std::uint64_t seed,
                               const std::vector<std::size_t> &sppFamily,
                               const SetProgress &progress) {
  PreparedBackend out;
  if (backend.sets == BackendSets::None) {
    out.spec = backend.spec;
    return out;
  }
  const auto start = Clock::now();
  std::shared_ptr<const LobeTables> tables;
  std::vector<const Target *> lobeTargets;
  if (backend.makesLobeSets() && settings.integrator != IntegratorKind::Light) {
    tables = scene.lobeTables->get(scene.materials, lobeTablesFor(settings));
    VisitedBins bins = visitedBins(scene, settings, *tables, sceneName);
    lobeTargets = std::move(bins.targets);
    out.note = std::move(bins.note);
  }
  const BackendPlan plan =
      planBackend(backend, settings.integrator, sampledLight(scene, settings.integrator),
                  tables.get(), lobeTargets, sceneName, settings.spp, sets, seed, sppFamily);
  if (!plan.spec) throw std::invalid_argument("backend '" + backend.word + "': " + plan.why);
  out.spec = *plan.spec;
  const std::vector<SetsJob> made = makeMissingSets(
      Ranks::world(), plan.sets,
      [&](std::size_t done, std::size_t total, const SetsJob &job, int e, int n, double loss) {
        if (progress)
          progress("optimize sets", (double(done) + double(e) / n) / double(total),
                   job.label + ": loss " + formatNumber(loss));
      });
  // Made: written by this call (makeMissingSets); every other set was in
  // the cache already, or another process wrote it meanwhile.
  out.setsMade = made.size();
  out.setsCached = plan.sets.size() - std::min(plan.sets.size(), made.size()) + plan.found.size();
  for (const SetsJob &job : plan.sets)
    out.sets.push_back({job.file.string(), shortSpec(job.target->spec()),
                        std::any_of(made.begin(), made.end(),
                                    [&](const SetsJob &m) { return m.file == job.file; })});
  for (const BackendPlan::Found &f : plan.found)
    out.sets.push_back({f.file.string(), shortSpec(f.target->spec()), false});
  out.setupSeconds = made.empty() ? 0.0 : secondsSince(start);
  return out;
}

}  // namespace nuld
