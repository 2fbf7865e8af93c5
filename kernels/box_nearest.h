// nearest_in_grid's answer (kernels/grid_nearest.h) for the frame matcher's lookups on the
// host (kernels/frame_matcher.h), in about half its time. nearest_in_grid grows spheres from a
// first radius and walks, for each, the rows of cells the sphere meets, with a square root, two
// gaps and two clamped bounds a row. Here each of those spheres is walked as the box of cells
// that holds it (the same bounds along z and y, along x the widest row's), every row the same
// span: one pair of cell offsets a row. The box holds every cell nearest_in_grid walks for the
// sphere, so the answers agree when the nearest point in the box lies inside the sphere by a
// margin far above float rounding (its cell is then one nearest_in_grid walks, and equal
// distances go to the first in cell order in both), when nothing in the box lies within the
// sphere (nor does anything nearest_in_grid walks), and while the points of the boxes walked
// stay under nearest_in_grid's budget of kMaxCandidates. A query where one of these fails (a
// crowded box, a nearest point at the sphere's rim) is answered by nearest_in_grid itself.
#pragma once

#include <cstdint>

#include "kernels/grid.h"
#include "kernels/vec3.h"

namespace fq {

/// nearest_in_grid(g, p, reach, first_radius).
uint32_t nearest_in_grid_boxes(const GridView& g, Vec3 p, float reach, float first_radius);

}  // namespace fq
