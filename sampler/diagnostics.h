#pragma once
// Warnings: input the program accepts but the user must hear about (a
// negative pixel treated as zero, a triangle of zero area). Library code
// reports them here rather than printing; the default handler prints
// "nuld: warning: MESSAGE" on stderr, once per distinct message (a map read
// for every cell of a study warns once). Tests install their own handler.

#include <functional>
#include <string>

namespace nuld {

void warning(const std::string &message);

using WarningHandler = std::function<void(const std::string &)>;
// Installs `handler` (an empty one restores the default) and returns the
// previous one.
WarningHandler setWarningHandler(WarningHandler handler);

}  // namespace nuld
