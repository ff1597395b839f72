#pragma once
// A high-spp reference render, built in passes so that it can be interrupted
// and resumed: pass p renders `passSpp` samples per pixel with the backend
// seeded `seed + p`, and the reference is the mean of the passes. After every
// pass the running sum and a small state file are written atomically; a
// resumed run adds the same float images in the same order, so it ends
// bit-identical to an uninterrupted one.
//
// Averaging independently randomized passes keeps the estimate unbiased for
// any backend; with Halton (the paper's choice for references) each pass is a
// fresh random-digit-permuted Halton set.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "renderer/render.h"
#include "renderer/scene.h"

namespace nuld::study {

struct ReferenceSettings {
  std::string backend = "halton";
  std::size_t spp = 4096;     // in all; a multiple of passSpp is rounded up to
  std::size_t passSpp = 256;  // samples per pixel of one pass
  std::uint64_t seed = 1u << 20;
  RenderSettings render;  // resolution, integrator, depth (its spp is ignored)

  // A reference smaller than one pass is one pass of `spp`; otherwise spp
  // is rounded up to whole passes.
  std::size_t samplesPerPass() const { return std::min(spp, passSpp); }
  std::size_t passes() const { return (spp + samplesPerPass() - 1) / samplesPerPass(); }
  std::size_t totalSpp() const { return passes() * samplesPerPass(); }
  // "key=value ..." of everything the image depends on; a state file made
  // with another description is refused rather than silently mixed in.
  std::string describe(const std::string &sceneName) const;
};

struct ReferenceProgress {
  std::size_t passesDone = 0, passes = 0;
  double fraction = 0;  // of the whole reference, counting the pass in flight
};

struct ReferenceResult {
  Image image;
  double seconds = 0;         // render time of the passes rendered by this run
  double totalSeconds = 0;    // of all passes so far, over every run
  std::size_t passesRun = 0;  // 0 when the reference was already complete
  bool complete = false;      // false: stopped early, image is the passes so far
};

// Renders (or resumes, or simply reads) the reference in `dir`:
// dir/reference.exr (+ .png) when complete, dir/reference.partial.exr and
// dir/reference.state while in progress. `stopAfterPasses` (0: no limit)
// ends the run early with the partial state saved, for tests and for long
// references spread over several sessions.
//
// Under MPI (ranks.h) the ranks render one pass each per round and rank 0
// adds them in pass order and alone writes the files: the image is
// bit-identical for any rank count, and every rank returns it.
ReferenceResult renderReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const std::filesystem::path &dir,
                                const std::function<void(const ReferenceProgress &)> &progress = {},
                                std::size_t stopAfterPasses = 0);

}  // namespace nuld::study
