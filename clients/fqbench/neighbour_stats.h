// Neighbour counts behind the FLOP floors in docs/BENCHMARKS.md: how many points each
// neighbourhood pass visits per vertex at a row's radii (CPU, through the same grid and
// visitor as the engines).
#pragma once

#include "core/mesh_view.h"
#include "core/params.h"

namespace fq::bench {

struct NeighbourStats {
  double nbhd = 0.0;       ///< mean neighbours within 2 sigma_b (Q')
  double diffusion = 0.0;  ///< within 2 sigma_s (diffusion, BF)
  double cluster = 0.0;    ///< within 2 sigma_d (score, link); 0 without clustering
};

/// Mean neighbour counts per vertex for `params` on `mesh` (grid cell = sigma_s).
NeighbourStats neighbour_stats(const MeshView& mesh, const Params& params);

}  // namespace fq::bench
