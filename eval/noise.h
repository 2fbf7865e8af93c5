// Synthetic noise for denoising experiments, reproducible across platforms.
#pragma once

#include <cstdint>

#include "core/mesh_view.h"

namespace fq {

/// Adds isotropic Gaussian noise to every coordinate of every vertex: independent draws
/// with standard deviation `sigma_mean_edges * mean_edge_length(mesh)` (the paper's unit,
/// so a sigma of 0.3 means "30% of the mean edge" whatever the mesh's scale).
///
/// The draws come from std::mt19937_64 through our own Box–Muller transform rather than
/// std::normal_distribution, whose algorithm is implementation-defined: the same seed
/// gives the same mesh with every standard library. Draw order is vertex order, x, y, z.
///
/// A sigma that is not > 0 and finite, or a mesh without a non-degenerate edge, leaves
/// the mesh unchanged (there is no meaningful amplitude to add).
void add_gaussian_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed);

/// Noise along the surface normal only: each vertex moves by one draw of the same standard
/// deviation along its unit area-weighted normal (of the mesh before noise), so the noise
/// roughens the surface without sliding vertices along it. Same draws and checks as
/// add_gaussian_noise (one draw per vertex, vertex order); vertices without a normal
/// (isolated, or only degenerate faces) stay put.
void add_normal_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed);

}  // namespace fq
