#include "sampler/io/input_file.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace nuld {

void requireInputFile(const std::string &path, const std::string &what) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  const char *reason = nullptr;
  if (ec || !std::filesystem::exists(status))
    reason = "no such file";
  else if (std::filesystem::is_directory(status))
    reason = "it is a directory";
  else if (!std::filesystem::is_regular_file(status))
    reason = "not a regular file (a device, pipe or socket)";
  if (reason) throw std::runtime_error(path + ": cannot open " + what + ": " + reason);
}

std::string quotedInput(std::string_view text, std::size_t maxChars) {
  for (const char c : text)
    if (!(c == '\t' || (c >= 0x20 && c < 0x7f)))
      return "<" + std::to_string(text.size()) + " bytes of binary data>";
  if (text.size() <= maxChars) return "'" + std::string(text) + "'";
  return "'" + std::string(text.substr(0, maxChars)) + "...'";
}

}  // namespace nuld
