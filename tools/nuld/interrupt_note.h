#pragma once
// While an InterruptNote is alive, Ctrl-C (SIGINT) or SIGTERM ends the
// program with a note saying where the last checkpoint is and how to
// continue, rather than dying silently in the middle of a long run. The
// checkpoints themselves are written atomically by the run driver
// (sampler/optimize/resumable_run.h), so the file named is never half
// written.

#include <string>

namespace nuld::cli {

class InterruptNote {
 public:
  explicit InterruptNote(const std::string &checkpoint);
  ~InterruptNote();
  InterruptNote(const InterruptNote &) = delete;
  InterruptNote &operator=(const InterruptNote &) = delete;
};

}  // namespace nuld::cli
