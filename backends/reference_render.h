#pragma once
// A high-spp reference render, built in passes so that it can be interrupted
// and resumed: pass p renders `passSpp` samples per pixel with the backend
// seeded `seed + p`, and the reference is the mean of the passes. After every
// pass the running sums and a small state file are written atomically; a
// resumed run adds the same float images in the same order, so it ends
// bit-identical to an uninterrupted one.
//
// Averaging independently randomized passes keeps the estimate unbiased for
// any backend; with Halton (the paper's choice for references) each pass is a
// fresh random-digit-permuted Halton set.
//
// The passes form two independent halves, the even and the odd ones, kept as
// two sums: the reference is their mean, and their difference measures the
// reference's own noise (ReferenceNoise), which every MSE against it
// contains. A reference made before the halves existed is refused.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "renderer/render.h"
#include "renderer/scene.h"

namespace nuld {

struct ReferenceSettings {
  std::string backend = "halton";
  std::size_t spp = 4096;     // in all; rounded up to an even number of passes
  std::size_t passSpp = 256;  // samples per pixel of one pass, at most
  std::uint64_t seed = 1u << 20;
  RenderSettings render;  // resolution, integrator, depth (its spp is ignored)

  // Two halves of equal spp: an even number of passes, at least two. A
  // reference smaller than two passes is two passes of half its spp;
  // otherwise spp is rounded up to whole pairs of passes.
  std::size_t samplesPerPass() const {
    return std::max<std::size_t>(1, std::min(passSpp, (spp + 1) / 2));
  }
  std::size_t passes() const {
    const std::size_t pair = 2 * samplesPerPass();
    return 2 * std::max<std::size_t>(1, (spp + pair - 1) / pair);
  }
  std::size_t totalSpp() const { return passes() * samplesPerPass(); }
  // "key=value ..." of everything the image depends on: the scene's content
  // (sceneContentKey) and every setting above that changes a pixel. A state
  // file made with another description is refused rather than silently
  // mixed in, and the reference cache keys by it (reference_cache.h).
  std::string describe(const Scene &scene) const;
};

struct ReferenceProgress {
  std::size_t passesDone = 0, passes = 0;
  double fraction = 0;  // of the whole reference, counting the pass in flight
  // Another process is making the same reference in the cache and this one
  // waits for it (reference_cache.h); nothing else is set then.
  bool waiting = false;
};
// What a progress bar says of it: "pass 3/16", or that it waits.
std::string referenceProgressText(const ReferenceProgress &p);

// What DIR/reference.state says of a reference in progress or complete: its
// description, the passes done and their render seconds over every run.
struct ReferenceState {
  std::string description;
  std::size_t passesDone = 0;
  double seconds = 0;
};
// Throws std::runtime_error naming the file when it cannot be read or a
// field is not a number.
ReferenceState readReferenceState(const std::filesystem::path &file);

// Why the reference in `dir` would not be used ("" when it would): its
// state does not read, or an image it counts (the reference and its halves
// when complete, the partial sums while in progress) does not decode, was
// made for another reference, or does not match the hash of its pixels
// recorded in it. The checks every use makes (renderReference), without
// changing anything.
std::string referenceProblem(const std::filesystem::path &dir);

// A reference's own noise, from its two halves h0 and h1 (each the mean of
// half the passes, so of twice the reference's variance v per pixel):
// E[(h0 - h1)^2] = 4 v, so v is estimated by a quarter of their mean squared
// difference. `variance` is averaged over pixels and channels as MSE is,
// `relVariance` weighted as relMSE is (renderer/image_metrics.h): the
// expected amount by which the reference's noise raises every MSE and relMSE
// measured against it.
struct ReferenceNoise {
  double variance = 0, relVariance = 0;
};
// Throws std::invalid_argument when the sizes differ.
ReferenceNoise referenceNoise(const Image &half0, const Image &half1);

struct ReferenceResult {
  Image image;
  ReferenceNoise noise;       // of the complete reference (zero while incomplete)
  double seconds = 0;         // render time of the passes rendered by this run
  double totalSeconds = 0;    // of all passes so far, over every run
  std::size_t passesRun = 0;  // 0 when the reference was already complete
  bool complete = false;      // false: stopped early, image is the passes so far
};

// Renders (or resumes, or simply reads) the reference in `dir`:
// dir/reference.exr (+ .png) and its halves dir/reference.half0.exr and
// .half1.exr (the means of the even and the odd passes) when complete,
// dir/reference.partial.exr (both sums, six channels, with the passes they
// hold) and dir/reference.state while in progress. A state or image of another
// description, or of a reference without halves, is refused, naming it. `stopAfterPasses` (0: no
// limit) ends the run early with the partial state saved, for tests and for long references spread
// over several sessions.
//
// Under MPI (ranks.h) the ranks render one pass each per round and rank 0
// adds them in pass order and alone writes the files: the image is
// bit-identical for any rank count, and every rank returns it.
// `description` is settings.describe(scene) when the caller has made it
// already (empty: made here; it hashes the whole scene).
ReferenceResult renderReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const std::filesystem::path &dir,
                                const std::function<void(const ReferenceProgress &)> &progress = {},
                                std::size_t stopAfterPasses = 0,
                                const std::string &description = {});

}  // namespace nuld
