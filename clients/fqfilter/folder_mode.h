// fqfilter on a folder: every mesh file in it, in name order, one engine for all.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "clients/fqfilter/cli_options.h"
#include "kernels/engine.h"

namespace fq::cli {

/// Regular files of `folder` with a readable mesh extension, sorted by file name.
std::vector<std::filesystem::path> list_mesh_files(const std::filesystem::path& folder);

/// Processes every mesh of options.input; outputs (when options.output is set) go to
/// that folder, created if missing, as <name>.ply. Prints a progress line per file and
/// a final count on stderr; reports go to stdout. A failing file does not stop the
/// others. Returns the process exit code: 0 when every file succeeded, 1 otherwise.
int run_folder(const Options& options, Engine& engine);

}  // namespace fq::cli
