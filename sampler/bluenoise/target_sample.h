#pragma once
// The stratified sample of a target that both blue-noise baselines use where
// the target has no closed form for them: the first `count` points of an
// Owen-scrambled Sobol set through the target's inverse CDF.

#include <cstdint>
#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target.h"

namespace nuld {

inline std::vector<Point2> stratifiedTargetSample(const Target &target, std::size_t count,
                                                  std::uint64_t seed) {
  std::vector<Point2> sample(count);
  generateSet({SequenceKind::Sobol, Scramble::Owen, seed}, 0, sample);
  for (Point2 &p : sample) p = target.invert(p).x;
  return sample;
}

}  // namespace nuld
