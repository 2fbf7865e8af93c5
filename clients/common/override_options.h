// Command-line options for per-frame parameter overrides (--sigma-s ... --compute), shared
// by fqpub and fqstreambench. Only the options given on the command line are set.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "proto/fq.pb.h"
#include "common/status.h"

namespace fq::client {

struct OverrideArgs {
  std::optional<float> sigma_s, sigma_r, sigma_b, sigma_n, tikhonov, sigma_d, sigma_q, theta;
  std::optional<bool> constrained, track_ids;
  std::optional<uint32_t> target_clusters, min_cluster_size, sticky_rings;
  std::string mode, cluster_method, compute, cluster_geometry;
};

/// Registers the options on `app` (in an "Parameter overrides" group).
void add_override_options(CLI::App& app, OverrideArgs& args);

/// The wire form of the given options; kInvalidArgument for an unknown mode/method/compute.
Status to_wire(const OverrideArgs& args, wire::ParamOverrides& out, wire::Compute& compute);

}  // namespace fq::client
