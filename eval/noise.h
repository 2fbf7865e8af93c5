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

// Structured noise, as real acquisition makes it, with the clean mesh as ground truth (the
// quality matrix's structured rows, docs/QUALITY.md). Each keeps the vertex count and order;
// the same checks as above apply (no noise without a meaningful amplitude).

/// Depth noise of a range scanner looking along −z: each vertex moves along z by one draw of
/// standard deviation sigma / max(|n_z|, 0.25) (n its unit area-weighted normal): a
/// triangulation scanner's depth error grows as the surface turns away from it, and a
/// surface facing it gets sigma along its normal. Vertices without a normal stay put.
void add_depth_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed);

/// Spatially correlated noise along the normal, of correlation length `length` mean edges:
/// offsets two points d apart correlate as exp(−d² / (2 length²)) (white draws smoothed by a
/// Gaussian of standard deviation length / √2, over the vertices within 3 length in space),
/// and every vertex's offset has standard deviation sigma. Noise that a filter working on one
/// or two rings reads as detail.
void add_correlated_noise(Mesh& mesh, double sigma_mean_edges, double length_mean_edges, uint64_t seed);

/// Scan-line ripples along the normal: sigma·√2·sin(2π x / (period · mean edge) + φ), a
/// stripe pattern along the mesh's x axis (RMS sigma), φ drawn from the seed.
void add_ripple_noise(Mesh& mesh, double sigma_mean_edges, double period_mean_edges, uint64_t seed);

/// The noise families by name, as fqfilter's --noise-kind and fq.add_noise(kind=) spell them.
enum class NoiseKind { kIso, kNormal, kDepth, kCorrelated, kRipple };

/// "iso", "normal", "depth", "correlated", "ripple"; false for another name.
bool parse_noise_kind(const char* name, NoiseKind& kind);
const char* noise_kind_name(NoiseKind kind);

/// Adds the family's noise; `length` is the correlated family's correlation length and the
/// ripples' period (mean edges), unused by the others.
void add_noise(Mesh& mesh, NoiseKind kind, double sigma_mean_edges, double length_mean_edges, uint64_t seed);

}  // namespace fq
