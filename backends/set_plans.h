#pragma once
// What a backend word needs for a scene (the render study's planning of
// many cells at once, and prepareBackend's for one render): the sets each
// word makes for a scene at one spp, and the lobe bins worth a bank.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/optimized_sets.h"
#include "backends/ready_backend.h"
#include "renderer/lobe_tables.h"
#include "renderer/scene.h"

namespace nuld {

// What a backend word needs at one spp: the renderer's backend, which reads
// the sets the jobs make and the nested entries found in the cache. No spec
// when the scene cannot use the backend (reason in `why`).
struct BackendPlan {
  std::optional<BackendSpec> spec;
  std::vector<SetsJob> sets;
  std::string why;
  struct Found {
    const Target *target = nullptr;
    std::filesystem::path file;
  };
  std::vector<Found> found;  // nested entries that serve this spp (nothing to make)
};

// The plan of `backend` for the scene at `spp` under `integrator`, its sets
// in the set cache (made or found there): environment-map sets for `light`
// (the light the integrator samples, sampledLight), lobe banks for `lobeTargets` only;
// optimized with `seed`, a nested bank for the largest of `sppFamily`
// (prepareBackend).
BackendPlan planBackend(const BackendWord &backend, IntegratorKind integrator,
                        const EnvironmentLight *light, const LobeTables *tables,
                        const std::vector<const Target *> &lobeTargets,
                        const std::string &sceneSlug, std::size_t spp, const SetSettings &sets,
                        std::uint64_t seed, const std::vector<std::size_t> &sppFamily);

// How many camera rays' first hits each serving lobe table takes (its bin of
// its material), over a raysPerSide x raysPerSide grid in every pixel of a
// width x height render: the tables a render's first bounce actually asks
// for, found by tracing primary rays only. Tables no ray reaches are absent.
struct LobeVisits {
  std::map<const Target *, std::size_t> rays;  // per table
  std::size_t total = 0;                       // camera rays traced
};
LobeVisits lobeTableVisits(const Scene &scene, const LobeTables &tables, int width, int height,
                           int raysPerSide = 2);

// The tabulated bins whose lobes get banks: those that at least a minimum share
// of the camera rays' first hits take (a 2 x 2 grid per pixel at the render's
// resolution; primary rays only, a fraction of a render's time), and a note
// naming the others.
struct VisitedBins {
  std::vector<const Target *> targets;
  std::string note;
};
VisitedBins visitedBins(const Scene &scene, const RenderSettings &settings,
                        const LobeTables &tables, const std::string &slug);

}  // namespace nuld
