#include "sampler/diagnostics.h"

#include <iostream>
#include <mutex>
#include <set>

namespace nuld {
namespace {

std::mutex mutex;
WarningHandler handler;
std::set<std::string> printed;

}  // namespace

void warning(const std::string &message) {
  const std::lock_guard lock(mutex);
  if (handler) {
    handler(message);
  } else if (printed.insert(message).second) {
    std::cerr << "nuld: warning: " << message << "\n";
  }
}

WarningHandler setWarningHandler(WarningHandler next) {
  const std::lock_guard lock(mutex);
  std::swap(handler, next);
  return next;
}

}  // namespace nuld
