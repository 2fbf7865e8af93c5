// How much neighbourhood work a frame's parameters ask for, estimated before the engine
// runs from the frame's plan (kernels/frame_plan.h): every neighbourhood pass of every engine
// run (the clustering geometry and clustering runs included) and the "qf+" refinement. Every
// sigma is in mean edges and neighbourhoods have radius 2 sigma, so on a surface sampled at
// about one vertex per (sqrt(3)/2) squared mean edges a vertex has about
// (2 / sqrt(3)) * pi * (2 sigma)^2 ~ 14.5 sigma^2 neighbours. A sigma of 1e4 is in range for
// the filter but asks for 1.45e9 neighbours per vertex: refused here with a message, instead
// of holding an engine for minutes.
#pragma once

#include <cstdint>

#include "common/status.h"
#include "core/params.h"

namespace fq::daemon {

/// Expected neighbours of one vertex within radius 2 sigma.
double expected_neighbours(double sigma);

/// "qf+": neighbour visits per vertex of a refinement for `noise` (mean edges; its rounds of
/// face-normal and vertex passes over triangle fans, kernels/refine_plan.h).
double expected_refine_visits(float noise);

/// The noise the budget plans "qf+" for when the frame's noise is estimated (the estimate comes
/// only from the frame itself): the heaviest noise fq's quality matrix measures
/// (docs/QUALITY.md), times the strength.
inline constexpr float kBudgetNoise = 0.5f;

/// Expected neighbour visits of one frame: every neighbourhood pass of the plan's runs times
/// `vertices`, and the refinement for the known noise or kBudgetNoise.
double expected_neighbour_work(const Params& p, uint32_t vertices);

/// kInvalidArgument naming the parameter whose pass dominates when the work is over `limit`.
/// `p` must be valid (validate(Params)).
Status check_work_budget(const Params& p, uint32_t vertices, double limit);

}  // namespace fq::daemon
