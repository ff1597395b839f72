// nuld study integrate: its implementation lands in the next commit; until
// then the subcommand says so instead of doing anything.
#include <stdexcept>

#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addStudyIntegrate(CLI::App &) {
  return []() -> int { throw std::runtime_error("study integrate: not built yet"); };
}

}  // namespace nuld::cli
