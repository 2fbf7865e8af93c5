// One mesh through fqfilter: read, optional noise, engine runs, metrics, write.
#pragma once

#include <string>

#include "clients/fqfilter/cli_options.h"
#include "kernels/engine.h"
#include "clients/fqfilter/file_report.h"
#include "common/status.h"

namespace fq::cli {

/// Processes `input` with `engine` and writes the result to `output` (nothing when
/// empty): filtered positions (or the input's when clustering only) and, with
/// clustering, the labels. Fills `report`; on failure also report.error, and the
/// returned status says what went wrong in one line naming the file.
Status run_file_job(const std::string& input, const std::string& output, const Options& options,
                    Engine& engine, FileReport& report);

}  // namespace fq::cli
