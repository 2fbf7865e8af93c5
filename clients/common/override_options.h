// Command-line options for per-frame parameter overrides (--sigma-s ... --compute), shared
// by fqpub and fqstreambench: one option per wire row of the parameter table
// (core/param_table.h). Only the options given on the command line are set.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "core/param_table.h"
#include "wire/fq.pb.h"

namespace fq::client {

struct OverrideArgs {
  std::vector<std::pair<const ParamRow*, std::string>>
      given;            ///< parameter options as typed, checked by to_wire
  std::string compute;  ///< a name, checked by to_wire
};

/// Registers the options on `app` (in an "Parameter overrides" group).
void add_override_options(CLI::App& app, OverrideArgs& args);

/// The wire form of the given options; kInvalidArgument naming the option for a bad value
/// (a number that is none, an unknown mode/method/geometry/compute).
Status to_wire(const OverrideArgs& args, wire::ParamOverrides& out, wire::Compute& compute);

}  // namespace fq::client
