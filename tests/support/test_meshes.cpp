#include "tests/support/test_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace fq::test {

namespace {

void add_vertex(Mesh& m, float x, float y, float z) { m.positions.insert(m.positions.end(), {x, y, z}); }

void add_triangle(Mesh& m, uint32_t a, uint32_t b, uint32_t c) {
  m.triangles.insert(m.triangles.end(), {a, b, c});
}

// Lattice point (i, j, k) in [0, n]^3 -> vertex index, created on first use so that the
// vertices on the cube's edges are shared by the faces that meet there.
class CubeLattice {
 public:
  CubeLattice(Mesh& mesh, int n, float half)
      : mesh_(mesh), n_(n), half_(half), index_(size_t(n + 1) * (n + 1) * (n + 1), kNone) {}

  uint32_t at(const int (&c)[3]) {
    uint32_t& slot = index_[(size_t(c[2]) * (n_ + 1) + c[1]) * (n_ + 1) + c[0]];
    if (slot == kNone) {
      slot = mesh_.num_vertices();
      auto coord = [&](int i) { return -half_ + 2.0f * half_ * float(i) / float(n_); };
      add_vertex(mesh_, coord(c[0]), coord(c[1]), coord(c[2]));
    }
    return slot;
  }

 private:
  static constexpr uint32_t kNone = ~0u;
  Mesh& mesh_;
  int n_;
  float half_;
  std::vector<uint32_t> index_;
};

// Midpoint vertex of edge (a, b), projected on the sphere, shared by both triangles.
uint32_t midpoint(Mesh& m, std::map<std::pair<uint32_t, uint32_t>, uint32_t>& cache, uint32_t a, uint32_t b,
                  float radius) {
  const auto key = std::minmax(a, b);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  const Vec3 p = 0.5f * (vertex(m, a) + vertex(m, b));
  const Vec3 q = (radius / std::sqrt(norm2(p))) * p;
  const uint32_t id = m.num_vertices();
  add_vertex(m, q.x, q.y, q.z);
  cache.emplace(key, id);
  return id;
}

}  // namespace

Mesh make_plane_grid(int nx, int ny, float spacing) {
  Mesh m;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) add_vertex(m, float(i) * spacing, float(j) * spacing, 0.f);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const uint32_t v00 = uint32_t(j * (nx + 1) + i), v10 = v00 + 1;
      const uint32_t v01 = v00 + uint32_t(nx + 1), v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        add_triangle(m, v00, v10, v11);
        add_triangle(m, v00, v11, v01);
      } else {
        add_triangle(m, v00, v10, v01);
        add_triangle(m, v10, v11, v01);
      }
    }
  }
  return m;
}

Mesh make_cube(int n, float half) {
  Mesh m;
  CubeLattice lattice(m, n, half);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // e_u x e_v = e_axis
    for (int side : {0, n}) {
      for (int p = 0; p < n; ++p) {
        for (int q = 0; q < n; ++q) {
          int c[4][3];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            c[k][axis] = side;
            c[k][u] = p + du[k];
            c[k][v] = q + dv[k];
          }
          const uint32_t a = lattice.at(c[0]), b = lattice.at(c[1]), d = lattice.at(c[2]),
                         e = lattice.at(c[3]);
          if (side == n) {
            add_triangle(m, a, b, d);
            add_triangle(m, a, d, e);
          } else {  // the face at the low side looks toward -e_axis
            add_triangle(m, a, d, b);
            add_triangle(m, a, e, d);
          }
        }
      }
    }
  }
  return m;
}

Mesh make_icosphere(int subdivisions, float radius) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  const float s = radius / std::sqrt(1.0f + t * t);
  Mesh m;
  const float v[12][3] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& p : v) add_vertex(m, s * p[0], s * p[1], s * p[2]);
  m.triangles = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                 6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> cache;
    std::vector<uint32_t> coarse;
    coarse.swap(m.triangles);
    for (size_t f = 0; f < coarse.size(); f += 3) {
      const uint32_t a = coarse[f], b = coarse[f + 1], c = coarse[f + 2];
      const uint32_t ab = midpoint(m, cache, a, b, radius), bc = midpoint(m, cache, b, c, radius),
                     ca = midpoint(m, cache, c, a, radius);
      add_triangle(m, a, ab, ca);
      add_triangle(m, b, bc, ab);
      add_triangle(m, c, ca, bc);
      add_triangle(m, ab, bc, ca);
    }
  }
  return m;
}

Mesh make_single_triangle() {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0.3f, 0.9f, 0};
  m.triangles = {0, 1, 2};
  return m;
}

Mesh make_non_manifold_fin() {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1};
  m.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  return m;
}

Mesh make_triangle_soup(const Mesh& mesh) {
  Mesh soup;
  for (uint32_t corner = 0; corner < mesh.triangles.size(); ++corner) {
    const Vec3 p = vertex(mesh, mesh.triangles[corner]);
    add_vertex(soup, p.x, p.y, p.z);
    soup.triangles.push_back(corner);
  }
  return soup;
}

Mesh split_along_seam(const Mesh& mesh, std::vector<uint32_t>& original, float cut) {
  const uint32_t n = mesh.num_vertices();
  std::vector<bool> side(mesh.num_triangles());
  std::vector<uint8_t> touches(n, 0);  // bit 0: a triangle off the side, bit 1: one on it
  for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
    const uint32_t* c = &mesh.triangles[3 * size_t(t)];
    side[t] = (vertex(mesh, c[0]).x + vertex(mesh, c[1]).x + vertex(mesh, c[2]).x) / 3.f > cut;
    for (int k = 0; k < 3; ++k) touches[c[k]] |= side[t] ? 2 : 1;
  }
  Mesh out = mesh;
  original.resize(n);
  for (uint32_t v = 0; v < n; ++v) original[v] = v;
  std::vector<uint32_t> copy_of(n, ~0u);
  for (uint32_t v = 0; v < n; ++v) {
    if (touches[v] != 3) continue;
    copy_of[v] = out.num_vertices();
    out.positions.insert(out.positions.end(), &mesh.positions[3 * size_t(v)],
                         &mesh.positions[3 * size_t(v)] + 3);
    original.push_back(v);
  }
  for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!side[t]) continue;
    for (size_t c = 3 * size_t(t); c < 3 * size_t(t) + 3; ++c) {
      if (copy_of[mesh.triangles[c]] != ~0u) out.triangles[c] = copy_of[mesh.triangles[c]];
    }
  }
  return out;
}

uint32_t append_isolated_vertex(Mesh& mesh, Vec3 p) {
  add_vertex(mesh, p.x, p.y, p.z);
  return mesh.num_vertices() - 1;
}

uint32_t append_zero_area_faces(Mesh& mesh, uint32_t count) {
  const uint32_t n = std::min(count, mesh.num_triangles());
  for (uint32_t t = 0; t < n; ++t) {
    const uint32_t a = mesh.triangles[3 * size_t(t)], b = mesh.triangles[3 * size_t(t) + 1];
    add_triangle(mesh, a, a, b);
    const Vec3 mid = 0.5f * (vertex(mesh, a) + vertex(mesh, b));
    add_triangle(mesh, a, append_isolated_vertex(mesh, mid), b);
  }
  return 2 * n;
}

Vec3 vertex(const Mesh& mesh, uint32_t i) { return vertex(mesh.positions, i); }

Vec3 vertex(const std::vector<float>& positions, uint32_t i) {
  return {positions[3 * size_t(i)], positions[3 * size_t(i) + 1], positions[3 * size_t(i) + 2]};
}

bool all_finite(const std::vector<float>& positions) {
  for (float x : positions) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

double max_displacement(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (size_t i = 0; i + 2 < a.size() && i + 2 < b.size(); i += 3) {
    const double dx = double(a[i]) - b[i], dy = double(a[i + 1]) - b[i + 1], dz = double(a[i + 2]) - b[i + 2];
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return worst;
}

}  // namespace fq::test
