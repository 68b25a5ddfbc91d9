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

// A file's bytes for reading without a copy: mapped read-only where it is a regular file (a
// large one is then neither zero-filled nor copied), read into memory otherwise. Safe for files
// replaced by rename, as writeFileAtomically writes them: the mapping keeps the old bytes. A
// file cut shorter in place while mapped would end the process (SIGBUS), so map only files
// this program writes that way.
class MappedFile {
public:
    MappedFile() = default;
    MappedFile(MappedFile&& other) noexcept;
    MappedFile& operator=(MappedFile&& other) noexcept;
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    ~MappedFile();

    std::string_view bytes() const { return mapped_ ? std::string_view(mapped_, size_) : std::string_view(read_); }

private:
    friend Result<MappedFile> mapFile(const std::string& path);
    char* mapped_ = nullptr;
    size_t size_ = 0;
    std::string read_;  // the bytes when the file could not be mapped
};
Result<MappedFile> mapFile(const std::string& path);
// A path's extension in lower case, with its dot (".obj"); empty when it has none.
std::string lowercaseExtension(const std::string& path);
Status writeFileAtomically(const std::string& path, std::string_view contents);

}  // namespace qp
