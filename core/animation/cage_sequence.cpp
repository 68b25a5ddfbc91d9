#include "animation/cage_sequence.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "mesh/obj_io.h"

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
        // Regular files only: a pattern may name any folder, and a device file (/dev/tty1) could block.
        std::error_code typeError;
        if (!it->is_regular_file(typeError)) continue;
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

Result<VertexKeys> loadSequenceKeys(const std::string& pattern, const Cage& reference) {
    Result<std::vector<SequenceFile>> files = sequenceFiles(pattern);
    if (!files) return files.error();
    std::vector<std::vector<glm::vec3>> frames;
    for (const SequenceFile& file : *files) {
        const std::string frame = "frame " + std::to_string(file.number) + " (" + file.path + ")";
        if (file.number > uint64_t(kMaxKeyFrame))
            return Error{frame + ": the number is too large (keys go on frames up to " + std::to_string(kMaxKeyFrame) + ")"};
        Result<std::vector<glm::vec3>> positions = loadSequenceFrame(file.path, reference);
        if (!positions) return Error{"frame " + std::to_string(file.number) + ": " + positions.error().message};
        frames.push_back(std::move(positions).value());
    }
    const uint32_t vertexCount = reference.vertexCount();
    VertexKeys keys;
    keys.offsets.resize(size_t(vertexCount) + 1);
    for (uint32_t v = 0; v <= vertexCount; ++v) keys.offsets[v] = uint32_t(size_t(v) * frames.size());
    keys.frames.reserve(size_t(vertexCount) * frames.size());
    keys.positions.reserve(size_t(vertexCount) * frames.size());
    for (uint32_t v = 0; v < vertexCount; ++v)
        for (size_t f = 0; f < frames.size(); ++f) {
            keys.frames.push_back(int32_t((*files)[f].number));
            keys.positions.push_back(frames[f][v]);
        }
    if (keys.frames.empty()) keys.offsets.clear();
    return keys;
}

}  // namespace qp
