#include "recovery.h"

#include <cstdlib>
#include <ctime>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "mesh/file_io.h"

namespace qp::editor {

namespace fs = std::filesystem;

namespace {
constexpr const char* kSceneFile = "autosave.json";
constexpr const char* kInfoFile = "autosave-info.json";
}  // namespace

std::string recoveryDirectory() {
    if (const char* dir = std::getenv("QUADPLAN_RECOVERY_DIR"); dir && dir[0]) return dir;
    if (const char* state = std::getenv("XDG_STATE_HOME"); state && state[0]) return (fs::path(state) / "quadplan").string();
    if (const char* home = std::getenv("HOME"); home && home[0])
        return (fs::path(home) / ".local" / "state" / "quadplan").string();
    return {};
}

std::string localTimeNow() {
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &local);
    return text;
}

Status writeRecovery(const std::string& directory, const Scene& scene, const RecoveryInfo& info) {
    if (directory.empty()) return Error{"no recovery directory (set HOME or QUADPLAN_RECOVERY_DIR)"};
    std::error_code error;
    fs::create_directories(directory, error);
    if (error) return Error{"cannot create the recovery directory '" + directory + "': " + error.message()};
    // The scene first: an info file always has its scene beside it.
    if (Status s = writeFileAtomically((fs::path(directory) / kSceneFile).string(), formatScene(scene, CageStorage::Inline)); !s)
        return s;
    const nlohmann::json json = {{"source", info.source}, {"saved_at", info.savedAt}};
    return writeFileAtomically((fs::path(directory) / kInfoFile).string(), json.dump(2) + "\n");
}

std::optional<RecoveryInfo> findRecovery(const std::string& directory) {
    if (directory.empty() || !fs::exists(fs::path(directory) / kSceneFile)) return std::nullopt;
    RecoveryInfo info;
    if (Result<std::string> text = readFile((fs::path(directory) / kInfoFile).string())) {
        nlohmann::json json = nlohmann::json::parse(*text, nullptr, false);
        if (json.is_object()) {
            info.source = json.value("source", "");
            info.savedAt = json.value("saved_at", "");
        }
    }
    return info;
}

Result<Scene> loadRecovery(const std::string& directory, std::vector<std::string>* warnings) {
    return loadScene((fs::path(directory) / kSceneFile).string(), warnings);
}

void removeRecovery(const std::string& directory) {
    if (directory.empty()) return;
    std::error_code ignored;
    fs::remove(fs::path(directory) / kInfoFile, ignored);
    fs::remove(fs::path(directory) / kSceneFile, ignored);
}

}  // namespace qp::editor
