// Whole-file reads and crash-safe writes.
//
// writeFileAtomically writes to a temporary file in the same directory, flushes it to disk,
// then renames it over the target and flushes the directory: a reader (or a crash at any
// moment) sees either the old file or the new one, never a half-written one. The temporary
// file is unnamed (O_TMPFILE) until it is complete, so a process killed mid-write leaves no
// litter (one killed in the instant between naming it and the rename leaves
// ".<name>.tmp-<pid>-<n>", which the next save of that file removes); a failed write removes it. Errors name the file and the system's reason ("No space
// left on device", "Permission denied", ...).
#pragma once

#include <string>
#include <string_view>

#include "mesh/result.h"

namespace qp {

Result<std::string> readFile(const std::string& path);
// A path's extension in lower case, with its dot (".obj"); empty when it has none.
std::string lowercaseExtension(const std::string& path);
Status writeFileAtomically(const std::string& path, std::string_view contents);

}  // namespace qp
