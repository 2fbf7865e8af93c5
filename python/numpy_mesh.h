// numpy arrays <-> fq meshes for the Python module. Conversions copy, with the GIL held;
// the engines then run on the copies with the GIL released.
#pragma once

#include <pybind11/numpy.h>

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"

namespace fq::py {

namespace pyb = pybind11;

/// V as (N, 3) floats of any float or integer dtype, F as (M, 3) integers in 0..N-1.
/// ValueError naming the argument for a wrong shape, a negative or out-of-range index,
/// or more than 2^32 - 1 vertices.
Mesh to_mesh(const pyb::handle& vertices, const pyb::handle& faces);

/// Positions only, same checks as to_mesh's V ("name" is used in messages).
std::vector<float> to_positions(const pyb::handle& vertices, const char* name);

/// (N, 3) array of `positions`: float64 when `like` is a float64 array (what Open3D and
/// most numpy code use), float32 otherwise.
pyb::array positions_array(const std::vector<float>& positions, const pyb::handle& like);

/// (M, 3) int64 faces (numpy's default integer, what indexing code expects).
pyb::array faces_array(const std::vector<uint32_t>& triangles);

/// 1-D uint32 labels.
pyb::array labels_array(const std::vector<uint32_t>& labels);

}  // namespace fq::py
