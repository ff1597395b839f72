#pragma once
// The studies' plots and HTML report are drawn by Python scripts under
// tools/study/ run with Debian's /usr/bin/python3 (which has matplotlib; the
// python3 first on PATH may not). The scripts are found beside the sources,
// or under $NULD_TOOLS_DIR when set (an installed or relocated checkout).

#include <filesystem>
#include <string>

namespace nuld::study {

// tools/ (the folder holding study/*.py).
std::filesystem::path toolsDir();

// Runs `/usr/bin/python3 tools/study/SCRIPT DIR`; returns its exit status, or
// -1 (with the reason in `why`) when the interpreter or script is missing.
int runStudyScript(const std::string &script, const std::filesystem::path &dir, std::string *why);

}  // namespace nuld::study
