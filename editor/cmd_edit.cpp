// `quadplan edit [SCENE_OR_CAGE]` and bare `quadplan`: the interactive editor (editor/app/).
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "editor_app.h"

namespace qp::cli {

namespace {

struct EditArgs {
    std::string path = QUADPLAN_DEFAULT_SCENE;
    std::string automation;
    bool validate = false, noVsync = false;
    double autosaveSeconds = 30.0;
    double coarseAboveMs = 100.0;
    std::string size = "1280x800";
    uint32_t depth = 6;
    std::string pluginDir;
};

int runEdit(const EditArgs& args, bool untitled) {
    editor::LaunchOptions options;
    options.path = args.path;
    options.untitled = untitled;
    options.automationScript = args.automation;
    options.validate = args.validate;
    options.vsync = !args.noVsync;
    options.autosaveSeconds = args.autosaveSeconds;
    options.coarseAboveMs = args.coarseAboveMs;
    options.planDepth = args.depth;
    options.pluginDir = args.pluginDir;
    unsigned w = 0, h = 0;
    char x = 0;
    if (std::sscanf(args.size.c_str(), "%u%c%u", &w, &x, &h) != 3 || (x != 'x' && x != 'X') || w < 320 || h < 240 ||
        w > 8192 || h > 8192) {
        std::fprintf(stderr, "error: --size must be WIDTHxHEIGHT, at least 320x240, got '%s'\n", args.size.c_str());
        return 1;
    }
    options.width = w;
    options.height = h;
    if (!std::filesystem::exists(args.path)) {
        std::fprintf(stderr, "error: '%s' does not exist\n", args.path.c_str());
        return 1;
    }
    return editor::runEditorApp(options);
}

}  // namespace

int runEditor(const std::string& scenePath) {
    EditArgs args;
    args.path = scenePath;
    return runEdit(args, scenePath == QUADPLAN_DEFAULT_SCENE);
}

void registerEdit(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("edit", "Open the interactive editor on a scene (.json) or cage (.obj)");
    auto args = std::make_shared<EditArgs>();
    cmd->add_option("scene", args->path, "Scene or cage to open (default: the bundled default scene)");
    cmd->add_option("--automation", args->automation,
                    "Replay editor commands from FILE ('-': stdin); see docs/editor.md");
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation; any message makes the exit status 4");
    cmd->add_flag("--no-vsync", args->noVsync, "Present without waiting for the display (for measurements)");
    cmd->add_option("--autosave-seconds", args->autosaveSeconds, "Autosave interval while there are unsaved changes")
        ->check(CLI::Range(1.0, 3600.0));
    cmd->add_option("--coarse-above", args->coarseAboveMs,
                    "Progressive refinement: while the camera moves, draw coarse frames when full ones take longer "
                    "than MS on the device (default 100; 0: always)")
        ->check(CLI::Range(0.0, 60000.0));
    cmd->add_option("--size", args->size, "Window size, WIDTHxHEIGHT (default 1280x800)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, 10u));
    cmd->add_option("--plugin-dir", args->pluginDir,
                    "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->callback([args, cmd, &exitCode] {
        exitCode = runEdit(*args, cmd->count("scene") == 0);
    });
}

}  // namespace qp::cli
