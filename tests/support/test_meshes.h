// Meshes made in code for unit tests (as pmp-library's tests/helpers.h): regular shapes
// whose exact geometry is known, and small broken meshes for robustness tests.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/vec3.h"

namespace fq::test {

/// Square grid of nx x ny quads in the plane z = 0, each split into two triangles along
/// alternating diagonals; vertex (i, j) is at (i * spacing, j * spacing, 0) with index
/// j * (nx + 1) + i. Normals point to +z. Open: its border is a boundary.
Mesh make_plane_grid(int nx, int ny, float spacing = 1.0f);

/// Closed axis-aligned cube [-half, half]^3 with n x n quads (two triangles each) per
/// face; vertices on the cube's edges and corners are shared between faces, so the mesh
/// is closed and manifold: 6 n^2 + 2 vertices, 12 n^2 triangles, normals outward.
Mesh make_cube(int n, float half = 1.0f);

/// Icosahedron subdivided 1:4 `subdivisions` times, every vertex on the sphere of
/// `radius` about the origin: 10 * 4^s + 2 vertices, 20 * 4^s triangles, normals outward.
Mesh make_icosphere(int subdivisions, float radius = 1.0f);

/// One triangle in the plane z = 0.
Mesh make_single_triangle();

/// Three triangles sharing the edge (0, 1): a non-manifold "fin" (the third triangle
/// stands perpendicular to the other two, which lie in z = 0).
Mesh make_non_manifold_fin();

/// Every triangle with its own three vertices: coincident vertices with different indices
/// (as a quantized scan gives), the same surface as `mesh`.
Mesh make_triangle_soup(const Mesh& mesh);

/// `mesh` cut open along a seam, as an export's UV or normal seam leaves it: every vertex shared
/// by a triangle whose centroid has x > `cut` and one whose centroid has not is copied (the
/// copies appended in vertex order, at the bit-identical position) and the triangles with
/// x > `cut` reference the copies. `original` gets, per vertex of the result, the vertex of
/// `mesh` it is (itself for the first num_vertices()).
Mesh split_along_seam(const Mesh& mesh, std::vector<uint32_t>& original, float cut = 0.f);

/// Appends a vertex that no triangle references; returns its index.
uint32_t append_isolated_vertex(Mesh& mesh, Vec3 p);

/// Appends zero-area triangles along the first `count` triangles' first edge (a, b):
/// one with a repeated index (a, a, b) and one collinear (a, m, b) through a new vertex
/// m at the edge midpoint. Returns the number of triangles appended (2 * count).
uint32_t append_zero_area_faces(Mesh& mesh, uint32_t count);

/// Position of vertex i.
Vec3 vertex(const Mesh& mesh, uint32_t i);
Vec3 vertex(const std::vector<float>& positions, uint32_t i);

/// True when every coordinate is finite.
bool all_finite(const std::vector<float>& positions);

/// Largest distance between corresponding vertices of two position arrays (same size).
double max_displacement(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace fq::test
