// Command-line options for per-frame parameter overrides (--sigma-s ... --compute), shared
// by fqpub and fqstreambench. Only the options given on the command line are set.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "wire/fq.pb.h"
#include "common/status.h"

namespace fq::client {

struct OverrideArgs {
  wire::ParamOverrides fields;  ///< the numeric and on/off options given, set as they are parsed
  std::string mode, cluster_method, compute, cluster_geometry;  ///< names, checked by to_wire
};

/// Registers the options on `app` (in an "Parameter overrides" group).
void add_override_options(CLI::App& app, OverrideArgs& args);

/// The wire form of the given options; kInvalidArgument for an unknown mode/method/compute.
Status to_wire(const OverrideArgs& args, wire::ParamOverrides& out, wire::Compute& compute);

}  // namespace fq::client
