// Reading files that come from outside: regular files only (a FIFO blocks forever, /dev/zero
// never ends, a folder is no file), never more bytes than a limit, and JSON nesting checked
// before a parser or serialiser recurses into it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "ndfmip/result.h"

namespace ndfmip {

// The bytes of `path` if it is a regular file of at most maxBytes. Errors, one line:
// "PATH: cannot read: No such file or directory", "... is a directory", "... not a regular
// file (a FIFO)", "... 5.0 GiB, above the limit of 4.0 GiB".
Result<std::string> readRegularFile(const std::string& path, int64_t maxBytes);

// An open read-only descriptor of `path` if it is a regular file (the caller closes it);
// errors as above.
Result<int> openRegularFile(const std::string& path);

// "" when no array or object in `text` is nested deeper than maxDepth, else the problem
// ("nested deeper than 64 levels at line 3"). Strings are skipped, so brackets in them do
// not count; the text need not be valid JSON.
std::string jsonNestingProblem(std::string_view text, int maxDepth);

// A parser's or a system's message as one line of ours: control characters (line breaks, and
// those quoted from a file) as spaces, no closing full stop.
std::string oneLine(std::string text);

// "PATH: problem" on one line: the form of every error about a file.
Error fileError(const std::string& path, const std::string& problem);

} // namespace ndfmip
