// Subcommands of the `quadplan` executable. Each registers its options on the CLI11 app and,
// when run, stores the process exit status in `exitCode`; messages for the user go to stderr.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace qp::cli {

// `quadplan info CAGE_OR_SCENE [--json]`
void registerInfo(CLI::App& app, int& exitCode);

// `quadplan check-limit CAGE [--samples N] [--depth D] [--json]`
void registerCheckLimit(CLI::App& app, int& exitCode);

// `quadplan plan-stats CAGE [--depth D] [--json]`
void registerPlanStats(CLI::App& app, int& exitCode);

// `quadplan cull-stats CAGE_OR_SCENE [--views N] [--scheme NAME] [--tess F] [--json]`: culling
// measured by drawing, with the check that nothing visible was culled
void registerCullStats(CLI::App& app, int& exitCode);

// `quadplan bench SUITE [--repeats R] [--out DIR] ...`: benchmarks against OpenSubdiv
void registerBench(CLI::App& app, int& exitCode);

// `quadplan render CAGE_OR_SCENE --out FILE.png [...]`
void registerRender(CLI::App& app, int& exitCode);

// `quadplan animate CAGE_OR_SCENE [--sequence GLOB] --out DIR [--frames A:B] [...] [--json]`: an
// animation (keys or an OBJ sequence) played headless into DIR/frame_NNNN.png
void registerAnimate(CLI::App& app, int& exitCode);

// `quadplan compare CAGE_OR_SCENE --schemes a,b,... --out FILE.png [--json]`: schemes side by
// side with their error against the exact limit surface
void registerCompare(CLI::App& app, int& exitCode);

// `quadplan export CAGE_OR_SCENE --out FILE.{glb,gltf,obj,ply,off,stl} [...]`: the limit surface
// as a welded, watertight triangle mesh
void registerExport(CLI::App& app, int& exitCode);

// `quadplan bake CAGE_OR_SCENE --out FILE.exr [--size N] [--uv linear|smooth] [--normal-map FILE.png]`:
// the sculpted displacement as an OpenEXR map in UV space
void registerBake(CLI::App& app, int& exitCode);

// `quadplan schemes [CAGE] [--json]`: the scheme plugins found (and what they do with a cage)
void registerSchemes(CLI::App& app, int& exitCode);

// `quadplan sculpt CAGE_OR_SCENE --out OUT.json --path "x,y,z;..." | --strokes FILE.json [...]`
void registerSculpt(CLI::App& app, int& exitCode);

// `quadplan run-script FILE.py [ARGS...]`: a Python script with the quadplan module importable
void registerRunScript(CLI::App& app, int& exitCode);

// `quadplan edit [SCENE]`: the interactive editor; also what a bare `quadplan` runs.
void registerEdit(CLI::App& app, int& exitCode);
int runEditor(const std::string& scenePath);

}  // namespace qp::cli
