#include <cstdio>

#include "commands.h"
#include "scene.h"

namespace qp::cli {

int runEditor(const std::string& scenePath) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(scenePath, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    // The interactive editor (GLFW + Dear ImGui + Vulkan) is not built yet; until it is, say so
    // plainly instead of pretending to open a window.
    std::fprintf(stderr,
                 "Loaded %s (%u vertices, %u faces).\n"
                 "The interactive editor is not available in this build yet; "
                 "see `quadplan --help` for the headless commands.\n",
                 scenePath.c_str(), scene->cage.vertexCount(), scene->cage.faceCount());
    return 2;
}

void registerEdit(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("edit", "Open the interactive editor on a scene (.json) or cage (.obj)");
    auto path = std::make_shared<std::string>(QUADPLAN_DEFAULT_SCENE);
    cmd->add_option("scene", *path, "Scene or cage to open (default: the bundled default scene)");
    cmd->callback([path, &exitCode] { exitCode = runEditor(*path); });
}

}  // namespace qp::cli
