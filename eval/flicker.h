// Flicker of a filtered sequence: the frame-to-frame motion of the result that the clean
// sequence does not have. Viewers notice a surface point that jumps between frames more than
// a static error of the same size.
#pragma once

#include <cstdint>

namespace fq {

/// RMS over vertices of |(r − r_prev) − (c − c_prev)|, in units of `mean_edge`: r and r_prev
/// the results of two consecutive frames, c and c_prev their clean frames, 3 floats a vertex,
/// the same n vertices in the same order (fixed connectivity). 0 when n is 0.
double flicker(const float* r, const float* r_prev, const float* c, const float* c_prev, uint32_t n,
               double mean_edge);

/// flicker() split by the clean surface: `normal` the RMS of the difference's component along
/// the clean frame's unit vertex normal, `tangential` the RMS of the rest (total² = normal² +
/// tangential²). Motion across the surface is what viewers see; motion along it mostly is not.
struct FlickerParts {
  double total = 0.0, normal = 0.0, tangential = 0.0;
};

/// As flicker(), with `normals` the clean frame's unit vertex normals (3 doubles a vertex; a
/// zero normal puts the whole difference in the tangential part).
FlickerParts flicker_parts(const float* r, const float* r_prev, const float* c, const float* c_prev,
                           const double* normals, uint32_t n, double mean_edge);

}  // namespace fq
