// `--plan-db PATH` for subcommands that plan cages: the configuration database is loaded
// before planning and saved after, so later runs find their plans instead of building them.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "plans/plan_database.h"

namespace qp::cli {

inline void addPlanDatabaseOption(CLI::App* cmd, std::string& path) {
    cmd->add_option("--plan-db", path,
                    "Plan database file: loaded before planning (a damaged or stale file is rebuilt), saved after");
}

// A missing file is normal (first run); anything else wrong is a warning, never a failure.
inline void loadPlanDatabase(PlanDatabase& database, const std::string& path) {
    if (path.empty() || !std::filesystem::exists(path)) return;
    if (Status loaded = database.load(path); !loaded)
        std::fprintf(stderr, "warning: %s\n", loaded.error().message.c_str());
}

inline void savePlanDatabase(const PlanDatabase& database, const std::string& path) {
    if (path.empty() || database.misses() == 0) return;
    if (Status saved = database.save(path); !saved)
        std::fprintf(stderr, "warning: could not save the plan database: %s\n", saved.error().message.c_str());
}

}  // namespace qp::cli
