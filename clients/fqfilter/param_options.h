// fqfilter's parameter options, one per fqfilter row of the parameter table
// (core/param_table.h): --NAME-WITH-DASHES, the row's help, its default from the Params the
// options write into, its range or names checked by CLI11 as the value is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include "core/param_table.h"

namespace fq::cli {

/// Registers the fqfilter rows of `group`, in the table's order, writing into `p`. They take
/// the app's option_defaults() (its help group) like any other option.
void add_param_options(CLI::App& app, Params& p, ParamGroup group);

}  // namespace fq::cli
