#include "mesh/file_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace qp {

namespace {

std::string systemError(const std::string& what, const std::string& path) {
    return what + " '" + path + "': " + std::strerror(errno);
}

// The temporary file of a save in progress: closed and removed unless the save completes.
struct TempFile {
    int fd = -1;
    std::string name;  // empty while the file has no name (O_TMPFILE)
    ~TempFile() {
        if (fd >= 0) ::close(fd);
        if (!name.empty()) ::unlink(name.c_str());
    }
};

// Removes the named temporary files ".<name>.tmp-<pid>-<n>" that processes which no longer
// exist left beside `target` (killed between naming the finished file and the rename).
void removeOrphanedTempFiles(const std::filesystem::path& dir, const std::string& prefix) {
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        char* end = nullptr;
        const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
        if (pid <= 0 || *end != '-' || pid == ::getpid()) continue;
        if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) ::unlink(entry.path().c_str());
    }
}

}  // namespace

Result<std::string> readFile(const std::string& path) {
    // One read into a string of the file's size: a stream copied through a string stream grew by
    // doubling and copied the whole again, 1.4 s of a 573 MB plan database's 2 s load.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return Error{systemError("cannot open", path)};
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0) return Error{systemError("cannot read", path)};
    if (S_ISDIR(info.st_mode)) return Error{"cannot read '" + path + "': it is a directory"};
    std::string contents;
    // A regular file's size is a first guess; pipes and files that grow are read to their end.
    contents.resize(S_ISREG(info.st_mode) ? size_t(info.st_size) : 0);
    size_t filled = 0;
    char more[4096];  // read once the string is full: only growing files and pipes get here
    for (;;) {
        const bool full = filled == contents.size();
        const ssize_t got = full ? ::read(fd, more, sizeof(more))
                                 : ::read(fd, contents.data() + filled, contents.size() - filled);
        if (got < 0) {
            if (errno == EINTR) continue;
            return Error{systemError("cannot read", path)};
        }
        if (got == 0) break;
        if (full) contents.append(more, size_t(got));
        filled += size_t(got);
    }
    contents.resize(filled);
    return contents;
}

MappedFile::MappedFile(MappedFile&& other) noexcept
    : mapped_(std::exchange(other.mapped_, nullptr)), size_(std::exchange(other.size_, 0)), read_(std::move(other.read_)) {}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
    if (this != &other) {
        if (mapped_) ::munmap(mapped_, size_);
        mapped_ = std::exchange(other.mapped_, nullptr);
        size_ = std::exchange(other.size_, 0);
        read_ = std::move(other.read_);
    }
    return *this;
}

MappedFile::~MappedFile() {
    if (mapped_) ::munmap(mapped_, size_);
}

Result<MappedFile> mapFile(const std::string& path) {
    MappedFile file;
    struct stat info {};
    // Asked by name first: opening a pipe would wait for its writer, and readFile opens it again.
    if (::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return Error{systemError("cannot open", path)};
        if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0) {
            // Populated at once: one call instead of a fault per page as the reader walks it.
            void* at = ::mmap(nullptr, size_t(info.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
            if (at != MAP_FAILED) {
                file.mapped_ = static_cast<char*>(at);
                file.size_ = size_t(info.st_size);
            }
        }
        ::close(fd);
        if (file.mapped_) return file;
    }
    Result<std::string> bytes = readFile(path);
    if (!bytes) return bytes.error();
    file.read_ = std::move(bytes).value();
    return file;
}

Status writeFileAtomically(const std::string& path, std::string_view contents) {
    std::filesystem::path target(path);
    std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
    const std::string tempPrefix = (dir / ("." + target.filename().string() + ".tmp-")).string();

    // The data goes into an unnamed file (O_TMPFILE) that gets a name only once it is complete
    // and on disk, so a crash or kill -9 during the write leaves nothing behind. File systems
    // without O_TMPFILE get a named temporary file instead (which such a kill leaves behind).
    TempFile temp;
    temp.fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
    if (temp.fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
        temp.name = tempPrefix + "XXXXXX";
        temp.fd = mkstemp(temp.name.data());
        if (temp.fd < 0) temp.name.clear();
    }
    if (temp.fd < 0) return Error{systemError("cannot create a temporary file next to", path)};

    const char* data = contents.data();
    size_t left = contents.size();
    while (left > 0) {
        ssize_t written = ::write(temp.fd, data, left);
        if (written < 0) {
            if (errno == EINTR) continue;
            return Error{systemError("cannot write", path)};
        }
        data += written;
        left -= size_t(written);
    }
    if (::fsync(temp.fd) != 0) return Error{systemError("cannot flush", path)};
    if (temp.name.empty()) {
        // Name the finished file (a hard link to /proc/self/fd/N), then rename that over the
        // target: only a kill between these two calls leaves a temporary file, and the name
        // carries the pid so that the next save removes it.
        const std::string self = "/proc/self/fd/" + std::to_string(temp.fd);
        for (unsigned attempt = 0; temp.name.empty(); ++attempt) {
            std::string name = tempPrefix + std::to_string(::getpid()) + "-" + std::to_string(attempt);
            if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) temp.name = name;
            else if (errno != EEXIST || attempt > 100) return Error{systemError("cannot name the new file for", path)};
        }
    } else {
        // mkstemp creates 0600; saved scenes should be as readable as any other file.
        ::fchmod(temp.fd, 0644);
    }
    const int fd = std::exchange(temp.fd, -1);
    if (::close(fd) != 0) return Error{systemError("cannot flush", path)};
    if (::rename(temp.name.c_str(), path.c_str()) != 0) return Error{systemError("cannot replace", path)};
    temp.name.clear();
    removeOrphanedTempFiles(dir, "." + target.filename().string() + ".tmp-");
    // Persist the rename itself.
    int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
    return success();
}

std::string lowercaseExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace qp
