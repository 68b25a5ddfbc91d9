// Recovery: the autosave of unsaved work and the offer to restore it after a crash.
//
// While the document has unsaved changes the editor writes it every few seconds (atomically)
// to the recovery directory:
//   $QUADPLAN_RECOVERY_DIR, else $XDG_STATE_HOME/quadplan, else ~/.local/state/quadplan
// as `autosave.json` (the scene with its cage inline) and `autosave-info.json` (which file it
// came from, when it was written). Saving, or quitting and discarding the changes, deletes
// both; so finding them at start means the last session ended without either — a crash or a
// kill — and the editor offers to restore them. One recovery slot per user: a second editor
// running at the same time shares it.
#pragma once

#include <optional>
#include <string>

#include "mesh/result.h"
#include "scene/scene.h"

namespace qp::editor {

// Empty when none of the variables is set.
std::string recoveryDirectory();

struct RecoveryInfo {
    std::string source;   // the document's file; empty: it was untitled
    std::string savedAt;  // local time, "YYYY-MM-DD HH:MM:SS"
};

// Writes the scene and its info into `directory` (created when missing).
Status writeRecovery(const std::string& directory, const Scene& scene, const RecoveryInfo& info);
// The recovery waiting in `directory`, if any (a damaged info file still offers the scene).
std::optional<RecoveryInfo> findRecovery(const std::string& directory);
Result<Scene> loadRecovery(const std::string& directory, std::vector<std::string>* warnings = nullptr);
void removeRecovery(const std::string& directory);

std::string localTimeNow();

}  // namespace qp::editor
