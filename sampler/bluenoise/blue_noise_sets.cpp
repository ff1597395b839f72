#include "sampler/bluenoise/blue_noise_sets.h"

#include <stdexcept>

#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_spec.h"

namespace nuld {

std::string BlueNoiseRequest::name() const {
  return std::string(kBlueNoiseNames.name({method, mapped}));
}

BlueNoiseRequest parseBlueNoiseName(const std::string &name) {
  BlueNoiseRequest r;
  const BlueNoiseKind kind = kBlueNoiseNames.parse(name);
  r.method = kind.method;
  r.mapped = kind.mapped;
  return r;
}

PointSet blueNoiseSets(const BlueNoiseRequest &request, const Target &target, std::size_t n,
                       std::size_t instances, const std::function<void(long, long)> &progress) {
  const UniformTarget uniform;
  const Target &optimizeFor = request.mapped ? static_cast<const Target &>(uniform) : target;
  if (request.mapped && !target.hasInverse())
    throw std::invalid_argument("target '" + target.spec() + "' has no inverse CDF to map with");
  SlicedOtSettings sot = request.sot;
  GaussianBlueNoiseSettings gbn = request.gbn;
  sot.seed = gbn.seed = request.seed;
  const bool sliced = request.method == BlueNoiseMethod::SlicedOt;
  // Built once: the target's tabulated slices or sample, shared by the sets.
  std::unique_ptr<SliceDestinations> destinations;
  std::unique_ptr<GaussianBlueNoise> gaussian;
  if (sliced)
    destinations = std::make_unique<SliceDestinations>(optimizeFor, sot, n);
  else
    gaussian = std::make_unique<GaussianBlueNoise>(optimizeFor, gbn, n);
  const long iterations = sliced ? sot.iterations : gbn.iterations;
  const long total = long(instances) * iterations;

  PointSet set;
  set.n = n;
  set.points.resize(n * instances);
  for (std::size_t k = 0; k < instances; ++k) {
    const std::span<Point2> points = set.instance(k);
    Rng start(request.seed, hash3(0x57A27, k, n));
    for (Point2 &p : points) p = {start.uniform(), start.uniform()};
    // Gaussian blue noise only relaxes: its kernels reach a few spacings, so
    // a point that starts far outside the target's support never feels the
    // target's pull. Its adaptive sets start from independent target samples.
    if (!sliced && !optimizeFor.isUniform())
      for (Point2 &p : points) p = optimizeFor.invert(p).x;
    const auto step = [&](int it) {
      if (progress) progress(long(k) * iterations + it, total);
    };
    if (sliced)
      slicedOtTransport(*destinations, sot, std::uint32_t(k), points, step);
    else
      gaussian->optimize(points, step);
    if (request.mapped)
      for (Point2 &p : points) p = target.invert(p).x;
  }
  setMeta(set, meta::kGenerator, request.name());
  setMeta(set, sliced ? meta::kSlicedOt : meta::kGaussianBlueNoise,
          sliced ? sot.describe() : gbn.describe());
  if (!optimizeFor.isUniform())
    setMeta(set, meta::kTargetSamples,
            std::to_string(sliced ? sot.samplesFor(n) : gbn.samplesFor(n)));
  recordTarget(set, target);
  if (request.mapped) setMeta(set, meta::kMapping, std::string(meta::kInverseCdf));
  return set;
}

}  // namespace nuld
