#include "tools/study/report_script.h"

#include <sys/wait.h>

#include <cstdlib>

namespace nuld::study {

namespace fs = std::filesystem;

fs::path toolsDir() {
  if (const char *env = std::getenv("NULD_TOOLS_DIR"); env && *env) return env;
  return NULD_TOOLS_DIR;
}

namespace {

// Single quotes for the shell; embedded quotes closed, escaped and reopened.
std::string shellQuote(const std::string &s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

int runStudyScript(const std::string &script, const fs::path &dir, std::string *why) {
  const fs::path python = "/usr/bin/python3", path = toolsDir() / "study" / script;
  if (!fs::exists(python)) {
    if (why) *why = "/usr/bin/python3 not found (tools/setup.sh installs python3-matplotlib)";
    return -1;
  }
  if (!fs::exists(path)) {
    if (why) *why = path.string() + " not found (set NULD_TOOLS_DIR to the checkout's tools/)";
    return -1;
  }
  const std::string command = shellQuote(python.string()) + " " + shellQuote(path.string()) + " " +
                              shellQuote(dir.string());
  const int status = std::system(command.c_str());
  if (status == -1) {
    if (why) *why = "could not start " + python.string();
    return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace nuld::study
