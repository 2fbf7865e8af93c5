// How much neighbourhood work a frame's parameters ask for, estimated before the engine
// runs. Every sigma is in mean edges and neighbourhoods have radius 2 sigma, so on a
// surface sampled at about one vertex per (sqrt(3)/2) squared mean edges a vertex has
// about (2 / sqrt(3)) * pi * (2 sigma)^2 ~ 14.5 sigma^2 neighbours. A sigma of 1e4 is in
// range for the filter but asks for 1.45e9 neighbours per vertex: refused here with a
// message, instead of holding an engine for minutes.
#pragma once

#include <cstdint>

#include "common/status.h"
#include "core/params.h"

namespace fq::daemon {

/// Expected neighbours of one vertex within radius 2 sigma.
double expected_neighbours(double sigma);

/// Expected neighbour visits of one frame: every neighbourhood pass the parameters run
/// (base quadrics, diffusion, normal smoothing when constrained, clustering) times `vertices`.
double expected_neighbour_work(const Params& p, uint32_t vertices);

/// kInvalidArgument naming the sigma that dominates when the work is over `limit`.
Status check_work_budget(const Params& p, uint32_t vertices, double limit);

}  // namespace fq::daemon
