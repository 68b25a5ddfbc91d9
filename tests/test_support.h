// Helpers shared by the unit tests: where test data lives, and the shared shapes.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace qp::test {

inline std::string dataPath(const std::string& name) { return std::string(QUADPLAN_TEST_DATA) + "/" + name; }

inline std::filesystem::path sharedShapesDir() {
    return std::filesystem::path(QUADPLAN_SHARED_DIR) / "shapes";
}

inline bool haveSharedShapes() { return std::filesystem::is_directory(sharedShapesDir()); }

// Every OBJ in ../shared/shapes whose name starts with `prefix`, sorted by name.
inline std::vector<std::filesystem::path> sharedShapes(const std::string& prefix = "") {
    std::vector<std::filesystem::path> paths;
    if (!haveSharedShapes()) return paths;
    for (const auto& entry : std::filesystem::directory_iterator(sharedShapesDir()))
        if (entry.path().extension() == ".obj" && entry.path().filename().string().rfind(prefix, 0) == 0)
            paths.push_back(entry.path());
    std::sort(paths.begin(), paths.end());
    return paths;
}

// The names of the entries of a directory, sorted.
inline std::vector<std::string> listDirectory(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

#define QP_REQUIRE_SHARED_SHAPES()                                                             \
    if (!::qp::test::haveSharedShapes())                                                       \
    GTEST_SKIP() << "../shared/shapes is not beside the project; skipping shared-shape test"

}  // namespace qp::test
