#include <algorithm>
#include <cstring>
#include <limits>

#include "kernels/cuda/host_staging.h"
#include "kernels/parallel_for.h"

namespace fq::cuda {

void stage_points(const MeshView& mesh, const Normalization& norm, Point4* points, Vec3& lo, Vec3& hi) {
  const int64_t n = mesh.num_vertices;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float lx = kInf, ly = kInf, lz = kInf, hx = -kInf, hy = -kInf, hz = -kInf;
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel for schedule(static) reduction(min                                   \
                                                    : lx, ly, lz) reduction(max           \
                                                                            : hx, hy, hz) \
    num_threads(hardware_threads())
#endif
  for (int64_t i = 0; i < n; ++i) {
    const Vec3 p = norm.to_normalized(mesh.positions + 3 * i);
    points[i] = {p.x, p.y, p.z, 0.f};
    lx = std::min(lx, p.x);
    ly = std::min(ly, p.y);
    lz = std::min(lz, p.z);
    hx = std::max(hx, p.x);
    hy = std::max(hy, p.y);
    hz = std::max(hz, p.z);
  }
  lo = {lx, ly, lz};
  hi = {hx, hy, hz};
}

void copy_indices(const uint32_t* src, uint32_t* dst, size_t count) {
  constexpr size_t kChunk = size_t(1) << 18;
  const int64_t chunks = static_cast<int64_t>((count + kChunk - 1) / kChunk);
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel for schedule(static) num_threads(hardware_threads())
#endif
  for (int64_t c = 0; c < chunks; ++c) {
    const size_t begin = size_t(c) * kChunk, len = std::min(kChunk, count - begin);
    std::memcpy(dst + begin, src + begin, len * sizeof(uint32_t));
  }
}

void unstage_positions(const Vec3* moved, uint32_t n, const Normalization& norm, float* out) {
  parallel_for(n, hardware_threads(), [&](uint32_t i) { norm.to_input(moved[i], out + 3 * size_t(i)); });
}

}  // namespace fq::cuda
