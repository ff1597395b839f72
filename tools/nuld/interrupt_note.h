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
  // A command with --resume: "the last checkpoint is CHECKPOINT: run the
  // same command with --resume to continue from it".
  explicit InterruptNote(const std::string &checkpoint);
  // A command that resumes by itself (render, bank, study render): `where`
  // is the file or directory its checkpoints live in and `note` what the
  // note says once it exists.
  InterruptNote(const std::string &where, const std::string &note);
  ~InterruptNote();
  InterruptNote(const InterruptNote &) = delete;
  InterruptNote &operator=(const InterruptNote &) = delete;
};

}  // namespace nuld::cli
