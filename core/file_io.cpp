#include "file_io.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace qp {

namespace {

std::string systemError(const std::string& what, const std::string& path) {
    return what + " '" + path + "': " + std::strerror(errno);
}

}  // namespace

Result<std::string> readFile(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        return Error{"cannot read '" + path + "': it is a directory"};
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{systemError("cannot open", path)};
    std::ostringstream contents;
    contents << in.rdbuf();
    if (in.bad()) return Error{systemError("cannot read", path)};
    return contents.str();
}

Status writeFileAtomically(const std::string& path, std::string_view contents) {
    std::filesystem::path target(path);
    std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
    std::string temp = (dir / ("." + target.filename().string() + ".tmp-XXXXXX")).string();

    int fd = mkstemp(temp.data());
    if (fd < 0) return Error{systemError("cannot create a temporary file next to", path)};

    const char* data = contents.data();
    size_t left = contents.size();
    while (left > 0) {
        ssize_t written = ::write(fd, data, left);
        if (written < 0) {
            if (errno == EINTR) continue;
            std::string message = systemError("cannot write", path);
            ::close(fd);
            ::unlink(temp.c_str());
            return Error{message};
        }
        data += written;
        left -= size_t(written);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0) {
        std::string message = systemError("cannot flush", path);
        ::unlink(temp.c_str());
        return Error{message};
    }
    // mkstemp creates 0600; saved scenes should be as readable as any other file.
    ::chmod(temp.c_str(), 0644);
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        std::string message = systemError("cannot replace", path);
        ::unlink(temp.c_str());
        return Error{message};
    }
    // Persist the rename itself.
    int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
    return success();
}

}  // namespace qp
