#pragma once
// One driver for every long run that checkpoints and resumes: the direct
// optimizer's epochs (`nuld optimize`, the studies' cached sets) and the
// neural trainer's steps (`nuld train`). A run is cut into segments of about
// 5 % of its length; after each segment that does not end the run a
// checkpoint is written (atomically, by the run's own format), so an
// interrupted run loses at most one segment and a resumed one continues
// exactly where the checkpoint left it.

#include <functional>
#include <iosfwd>
#include <string>

namespace nuld {

// The flags every resumable command shares (registered by one CLI helper).
struct RunFlags {
  long checkpointEvery = 0;  // units per segment; 0: about 5 % of the run
  long stopAfter = -1;       // stop (with a checkpoint) after this unit; -1: run to the end
  bool resume = false;       // continue from the checkpoint when one exists
  // Start over, replacing an existing checkpoint. Without resume or fresh an
  // existing checkpoint is an error: it is never discarded silently.
  bool fresh = false;
  bool quiet = false;        // no progress bar or messages
};

// What a run offers the driver. `unit` names its steps in messages ("epoch",
// "step"); position() counts those done; advance(u) runs [position(), u).
struct ResumableRun {
  std::string unit;
  int total = 0;
  std::function<int()> position;
  std::function<void(int until)> advance;
  std::function<void(const std::string &path)> save, load;
  // Called after each segment, before its checkpoint (e.g. a validation whose
  // result the checkpoint records); optional.
  std::function<void()> segmentDone;
};

// The segment length the flags ask for: checkpointEvery, else total / 20.
int segmentLength(const RunFlags &flags, int total);

// Loads `checkpoint` when flags.resume is set and the file exists; says which
// on `log` (nullptr: silent). Call before creating a progress bar that should
// start at run.position().
void resumeRun(const ResumableRun &run, const std::string &checkpoint, const RunFlags &flags,
               std::ostream *log);

// Advances the run segment by segment up to flags.stopAfter (or its end),
// saving a checkpoint after each segment that does not end the run. Returns
// true when the run is complete: the caller then writes its result and
// removes the checkpoint. Returns false when it stopped early, saying so on
// `log`.
bool driveRun(const ResumableRun &run, const std::string &checkpoint, const RunFlags &flags,
              std::ostream *log);

}  // namespace nuld
