#pragma once
// Where a reader meets a path the user named: refuses what cannot be read as
// a file before opening it, naming the path and what it is. Opening a named
// pipe would block until something writes to it, and a device can read
// forever; a directory reads as nothing.

#include <string>
#include <string_view>

namespace nuld {

// Throws std::runtime_error "PATH: cannot open WHAT: REASON" (REASON: no such
// file, a directory, not a regular file (a device, pipe or socket)). `what`
// names the kind of file expected, e.g. "point-set file". Links are followed.
void requireInputFile(const std::string &path, const std::string &what);

// A piece of a file's text for an error message: 'TEXT' when it is printable
// ASCII (cut to `maxChars` with "..."), else "<N bytes of binary data>": a
// message never echoes a file's raw bytes (a binary file given as text
// would put control codes on the user's terminal).
std::string quotedInput(std::string_view text, std::size_t maxChars = 60);

}  // namespace nuld
