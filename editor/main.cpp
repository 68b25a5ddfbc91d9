// quadplan: Catmull-Clark subdivision-surface editor and toolbox.
// Without a subcommand it opens the editor on the default scene.

#include "commands.h"
#include "huge_page_malloc.h"

int main(int argc, char** argv) {
    qp::cli::useHugePagesForMalloc(argv);
    CLI::App app{"Quadplan: edit Catmull-Clark cages and render their exact limit surface "
                 "through subdivision plans.\nWithout a subcommand, opens the editor on the default scene."};
    app.set_version_flag("--version", QUADPLAN_VERSION);
    app.require_subcommand(0, 1);

    int exitCode = 0;
    qp::cli::registerEdit(app, exitCode);
    qp::cli::registerInfo(app, exitCode);
    qp::cli::registerCheckLimit(app, exitCode);
    qp::cli::registerPlanStats(app, exitCode);
    qp::cli::registerCullStats(app, exitCode);
    qp::cli::registerRender(app, exitCode);
    qp::cli::registerAnimate(app, exitCode);
    qp::cli::registerBench(app, exitCode);
    qp::cli::registerCompare(app, exitCode);
    qp::cli::registerExport(app, exitCode);
    qp::cli::registerBake(app, exitCode);
    qp::cli::registerSchemes(app, exitCode);
    qp::cli::registerSculpt(app, exitCode);
    qp::cli::registerRunScript(app, exitCode);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (app.get_subcommands().empty()) return qp::cli::runEditor(QUADPLAN_DEFAULT_SCENE);
    return exitCode;
}
