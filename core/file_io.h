// Whole-file reads and crash-safe writes.
//
// writeFileAtomically writes to a temporary file in the same directory, flushes it to disk,
// then renames it over the target: a reader (or a crash at any moment) sees either the old
// file or the new one, never a half-written one.
#pragma once

#include <string>
#include <string_view>

#include "result.h"

namespace qp {

Result<std::string> readFile(const std::string& path);
Status writeFileAtomically(const std::string& path, std::string_view contents);

}  // namespace qp
