// How stable are cluster labels from one frame to the next? The share of a frame's vertices
// whose label equals the label of the nearest vertex of the previous frame. 1 means every
// region kept its id; clusterings numbered independently per frame score near 1/K.
#pragma once

#include <cstdint>

namespace fq {

/// `prev` and `cur`: 3 floats per vertex and one label per vertex. `cell`: grid cell of the
/// nearest-vertex search (the mean edge length suits). NaN when `cur` has no vertex.
double label_persistence(const float* prev_xyz, const uint32_t* prev_labels, uint32_t prev_n,
                         const float* cur_xyz, const uint32_t* cur_labels, uint32_t cur_n, float cell,
                         int threads = 1);

}  // namespace fq
