#include "cage_sequence.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "obj_io.h"

namespace qp {

namespace fs = std::filesystem;

Result<std::vector<SequenceFile>> sequenceFiles(const std::string& pattern) {
    const fs::path path(pattern);
    const std::string name = path.filename().string();
    const size_t star = name.find('*');
    if (star == std::string::npos || name.find('*', star + 1) != std::string::npos)
        return Error{"the sequence pattern '" + pattern + "' must have one '*' in its file name, standing for the frame number"};
    const std::string prefix = name.substr(0, star), suffix = name.substr(star + 1);
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code error;
    std::vector<SequenceFile> files;
    for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
        const std::string candidate = it->path().filename().string();
        if (candidate.size() <= prefix.size() + suffix.size() || candidate.compare(0, prefix.size(), prefix) != 0 ||
            candidate.compare(candidate.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string digits = candidate.substr(prefix.size(), candidate.size() - prefix.size() - suffix.size());
        if (digits.size() > 18 || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
            continue;
        files.push_back({std::stoull(digits), it->path().string()});
    }
    if (error) return Error{"cannot list '" + folder.string() + "' for the sequence '" + pattern + "': " + error.message()};
    if (files.empty()) return Error{"no file matches the sequence '" + pattern + "'"};
    std::sort(files.begin(), files.end(), [](const SequenceFile& a, const SequenceFile& b) { return a.number < b.number; });
    for (size_t i = 1; i < files.size(); ++i) {
        if (files[i].number == files[i - 1].number)
            return Error{"the sequence '" + pattern + "' has frame " + std::to_string(files[i].number) + " twice: " +
                         files[i - 1].path + " and " + files[i].path};
        if (files[i].number != files[i - 1].number + 1)
            return Error{"the sequence '" + pattern + "' is missing frame " + std::to_string(files[i - 1].number + 1) +
                         " (between " + files[i - 1].path + " and " + files[i].path + ")"};
    }
    return files;
}

Result<std::vector<glm::vec3>> loadSequenceFrame(const std::string& path, const Cage& reference) {
    Result<Cage> frame = loadObj(path);
    if (!frame) return frame.error();
    if (frame->vertexCount() != reference.vertexCount())
        return Error{path + ": the frame has " + std::to_string(frame->vertexCount()) + " vertices, the cage " +
                     std::to_string(reference.vertexCount()) + " (a sequence keeps one topology)"};
    const uint32_t faces = std::min(frame->faceCount(), reference.faceCount());
    for (uint32_t f = 0; f < faces; ++f)
        if (frame->faceSize(f) != reference.faceSize(f) ||
            !std::equal(frame->faceBegin(f), frame->faceBegin(f) + frame->faceSize(f), reference.faceBegin(f)))
            return Error{path + ": face " + std::to_string(f) + " differs from the cage's (a sequence keeps one topology)"};
    if (frame->faceCount() != reference.faceCount())
        return Error{path + ": the frame has " + std::to_string(frame->faceCount()) + " faces, the cage " +
                     std::to_string(reference.faceCount()) + " (a sequence keeps one topology)"};
    return std::move(frame->positions);
}

}  // namespace qp
