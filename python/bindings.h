// The functions of the `fq` Python module, in two groups (see docs/PYTHON.md).
#pragma once

#include <pybind11/pybind11.h>

namespace fq::py {

/// filter, cluster, engine_name: the engines on numpy meshes.
void bind_engine_functions(pybind11::module_& m);

/// Stream: one stream's frames filtered in order with its history.
void bind_stream(pybind11::module_& m);

/// read_mesh, write_mesh, add_noise, metrics: files, noise and error measures.
void bind_mesh_functions(pybind11::module_& m);

/// surface_sample, surface_flicker: temporal measures on the result's surface.
void bind_surface_measures(pybind11::module_& m);
/// encode_frame, decode_result: fq.wire, frames and results as fqd's multipart messages.
void bind_wire(pybind11::module_& m);

/// Producer, Consumer: frames to fqd and results from it over ZeroMQ (fq_client).
void bind_client(pybind11::module_& m);

}  // namespace fq::py
