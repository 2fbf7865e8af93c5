// One mesh through fqfilter: read, optional noise, engine runs, metrics, write.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "clients/fqfilter/cli_options.h"
#include "clients/fqfilter/file_report.h"
#include "common/status.h"
#include "kernels/engine.h"

namespace fq::cli {

/// Processes `input` with `engine` and writes the result to `output` (nothing when
/// empty): filtered positions (or the input's when clustering only), with clustering the
/// labels, and what the input holds besides (a PLY's colours, normals recomputed from the
/// filtered surface unless options.keep_normals, an OBJ's per-corner normals within their
/// groups, texture coordinates, scalars, face properties) as far as the output
/// format can hold it. What is lost is warned about on stderr and listed in
/// report.warnings. Refuses to write over the input unless options.in_place. Fills
/// `report`; on failure also report.error, and the returned status says what went wrong in
/// one line naming the file.
/// With `kept`, also hands back what a sequence compares across frames: the reference's and
/// the result's positions (both empty when there is no reference or no filtering).
struct FramePositions {
  std::vector<float> reference, result;
  std::vector<uint32_t> triangles;  ///< the frame's, to tell a fixed connectivity from a re-meshed one
  double reference_mean_edge = 0.0;
};
Status run_file_job(const std::string& input, const std::string& output, const Options& options,
                    Engine& engine, FileReport& report, FramePositions* kept = nullptr);

/// True when both paths exist and name the same file (same device and inode, so also
/// through symbolic and hard links).
bool is_same_file(const std::string& a, const std::string& b);

}  // namespace fq::cli
