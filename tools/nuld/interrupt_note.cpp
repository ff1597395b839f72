#include "tools/nuld/interrupt_note.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>

namespace nuld::cli {
namespace {

// Prepared before any signal: a handler may only call async-signal-safe
// functions (access, write, _exit).
char checkpointPath[4096];
char withCheckpoint[4608];
char withoutCheckpoint[512];
struct sigaction previousInt, previousTerm;

void onInterrupt(int signal) {
  const bool saved = ::access(checkpointPath, F_OK) == 0;
  const char *note = saved ? withCheckpoint : withoutCheckpoint;
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, note, std::strlen(note));
  ::_exit(128 + signal);
}

}  // namespace

InterruptNote::InterruptNote(const std::string &checkpoint)
    : InterruptNote(checkpoint, "the last checkpoint is " + checkpoint +
                                    ": run the same command with --resume to continue from it") {}

InterruptNote::InterruptNote(const std::string &where, const std::string &note) {
  std::snprintf(checkpointPath, sizeof checkpointPath, "%s", where.c_str());
  std::snprintf(withCheckpoint, sizeof withCheckpoint, "\nnuld: interrupted; %s\n", note.c_str());
  std::snprintf(withoutCheckpoint, sizeof withoutCheckpoint,
                "\nnuld: interrupted before the first checkpoint; nothing was saved\n");
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previousInt);
  sigaction(SIGTERM, &action, &previousTerm);
}

InterruptNote::~InterruptNote() {
  sigaction(SIGINT, &previousInt, nullptr);
  sigaction(SIGTERM, &previousTerm, nullptr);
}

}  // namespace nuld::cli
