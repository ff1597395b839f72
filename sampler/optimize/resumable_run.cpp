#include "sampler/optimize/resumable_run.h"

#include <algorithm>
#include <filesystem>
#include <ostream>
#include <stdexcept>

namespace nuld {

int segmentLength(const RunFlags &flags, int total) {
  if (flags.checkpointEvery > 0) return int(std::min<long>(flags.checkpointEvery, 1L << 30));
  return std::max(1, total / 20);
}

void resumeRun(const ResumableRun &run, const std::string &checkpoint, const RunFlags &flags,
               std::ostream *log) {
  if (!flags.resume && !flags.fresh && std::filesystem::exists(checkpoint))
    throw std::runtime_error(checkpoint +
                             ": a checkpoint of an earlier run is here; pass "
                             "--resume to continue it, or --fresh to start over (replacing it)");
  if (flags.resume && std::filesystem::exists(checkpoint)) {
    run.load(checkpoint);
    if (log)
      *log << "resuming from " << checkpoint << " at " << run.unit << " " << run.position() << "\n";
  } else if (flags.resume && log) {
    *log << "no checkpoint at " << checkpoint << "; starting fresh\n";
  }
}

bool driveRun(const ResumableRun &run, const std::string &checkpoint, const RunFlags &flags,
              std::ostream *log) {
  const int every = segmentLength(flags, run.total);
  const int until =
      flags.stopAfter >= 0 ? int(std::min<long>(flags.stopAfter, run.total)) : run.total;
  while (run.position() < until) {
    const long next = (long(run.position()) / every + 1) * every;
    run.advance(int(std::min<long>(until, next)));
    if (run.segmentDone) run.segmentDone();
    if (run.position() < run.total) run.save(checkpoint);
  }
  if (run.position() >= run.total) return true;
  if (log)
    *log << "\nstopped after " << run.unit << " " << run.position() << "; checkpoint in "
         << checkpoint << " (continue with --resume)\n";
  return false;
}

}  // namespace nuld
