// What every mesh that enters fq is checked for (a frame before the engines, a frame before
// it is encoded): at least one vertex and one triangle, finite coordinates, every index in
// range. The scans run on `threads` threads (0 = all) and give the same answer for any
// thread count.
#pragma once

#include <cstdint>

#include "common/status.h"
#include "core/mesh_view.h"

namespace fq {

/// Non-empty, finite coordinates, every index in range, at least one triangle.
Status check_mesh(const MeshView& mesh, int threads = 0);

/// Index of the first non-finite value of values[0, count), or count; on `threads` threads
/// (0 = all), the same answer for any thread count.
uint64_t first_non_finite(const float* values, uint64_t count, int threads = 0);

/// check_mesh's first part: at least one vertex and one triangle.
Status check_mesh_counts(const MeshView& mesh);

/// check_mesh's verdict from the first non-finite coordinate (index into positions) and the
/// first out-of-range index (into triangles), each kNone when there is none, however they
/// were found (the CUDA engine searches on the device).
inline constexpr uint64_t kNone = ~uint64_t(0);
Status mesh_faults(const MeshView& mesh, uint64_t bad_coordinate, uint64_t bad_index);

}  // namespace fq
