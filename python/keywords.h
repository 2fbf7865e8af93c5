// The parameter keywords of fq.filter and fq.cluster: the rows of the parameter table
// (core/param_table.h) that name those functions among their surfaces. Defaults come from a
// default-constructed fq::Params, so Python's signatures and docstrings (which fq/_engine.py
// builds from these rows) follow the structs and never restate a default.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "core/param_table.h"

namespace fq::py {

/// The keywords `function` ("filter" or "cluster") takes besides V, F, engine and threads:
/// a list of (name, type, default, choices, help) tuples. type is "float", "int", "bool" or
/// "str"; choices is a list of names for "str", else None; float defaults are the shortest
/// decimal that gives the same float32 (0.7, not 0.699999988).
pybind11::list keyword_rows(const std::string& function);

/// Sets the members named by `keywords` (row names to values) in `params`. TypeError for an
/// unknown name or a value of the wrong type, ValueError for a name not among the choices or
/// a negative count. Ranges are left to fq::validate, as for every other surface.
void apply_keywords(const std::string& function, const pybind11::dict& keywords, Params& params);

/// Every row of the parameter table as (name, Python keyword, surfaces), surfaces a list of
/// "fqfilter", "toml", "wire", "filter", "cluster", "Stream", "report": for tests that walk it.
pybind11::list param_rows();

}  // namespace fq::py
