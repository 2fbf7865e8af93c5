// Quadric quick shift on the device: score and link with the CPU engine's math
// (cluster_math.h), roots by pointer jumping, labels compacted by a scan over the roots
// in input order -- the CPU's numbering (roots sorted by input index).
#include <cub/device/device_scan.cuh>

#include "kernels/cluster_math.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"
#include "kernels/gaussian.h"

namespace fq::cuda {

namespace {

__global__ void score_kernel(GridView g, const Quadric* bl, Gaussian gd, Gaussian gq, float radius,
                             bool euclid, float* score) {
  const uint64_t i = item_index();
  if (i < g.count) score[i] = representativity(g, bl, i, gd, gq, radius, euclid);
}

__global__ void link_kernel(GridView g, const Quadric* bl, const float* score, Gaussian gd, Gaussian gq,
                            float radius, bool euclid, float cut, uint32_t* next) {
  const uint64_t i = item_index();
  if (i < g.count) next[i] = quick_shift_link(g, bl, score, i, gd, gq, radius, euclid, cut);
}

// Asynchronous pointer jumping: each thread climbs its chain, rewriting its own link to
// the farthest ancestor seen so far, so threads that pass through it later skip ahead.
// Links only ever move up the same chain, so any value read is a valid ancestor.
__global__ void jump_to_roots(uint32_t n, uint32_t* root) {
  const uint64_t k = item_index();
  if (k >= n) return;
  volatile uint32_t* r = root;
  uint32_t cur = r[k];
  for (uint32_t up = r[cur]; up != cur; up = r[cur]) {
    cur = up;
    r[k] = cur;
  }
}

__global__ void flag_roots(uint32_t n, const uint32_t* rank, const uint32_t* next, uint32_t* flag) {
  const uint64_t i = item_index();
  if (i >= n) return;
  const uint32_t k = rank[i];
  flag[i] = next[k] == k ? 1u : 0u;
}

__global__ void label_kernel(uint32_t n, const uint32_t* rank, const uint32_t* order, const uint32_t* root,
                             const uint32_t* root_scan, uint32_t* labels) {
  const uint64_t i = item_index();
  if (i < n) labels[i] = root_scan[order[root[rank[i]]]];
}

}  // namespace

void cluster_scores(DeviceFrame& f, const RunPlan& run, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  const ClusterParams& p = run.params.clustering;
  FQ_LAUNCH(score_kernel, f.n, s, g, f.bl.data(), Gaussian::with_sigma(run.sigma_d.sigma),
            Gaussian::with_sigma(run.sigma_q), run.sigma_d.radius, p.method == ClusterMethod::kEuclidean,
            f.score.reserve(f.n));
}

void cluster_links(DeviceFrame& f, const RunPlan& run, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  const ClusterParams& p = run.params.clustering;
  FQ_LAUNCH(link_kernel, f.n, s, g, f.bl.data(), f.score.data(), Gaussian::with_sigma(run.sigma_d.sigma),
            Gaussian::with_sigma(run.sigma_q), run.sigma_d.radius, p.method == ClusterMethod::kEuclidean,
            1.0f - p.theta, f.next.reserve(f.n));
}

void cluster_labels(DeviceFrame& f, cudaStream_t s) {
  const uint32_t n = f.n;
  uint32_t* root = f.root.reserve(n);
  uint32_t* flag = f.root_flag.reserve(n + 1);
  uint32_t* scan = f.root_scan.reserve(n + 1);
  size_t bytes = 0;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, flag, scan, int(n + 1), s));
  unsigned char* temp = f.temp.reserve(bytes);
  uint32_t* labels = f.labels.reserve(n + 1);

  FQ_CUDA_CHECK(cudaMemcpyAsync(root, f.next.data(), n * sizeof(uint32_t), cudaMemcpyDeviceToDevice, s));
  FQ_LAUNCH(jump_to_roots, n, s, n, root);
  FQ_CUDA_CHECK(cudaMemsetAsync(flag + n, 0, sizeof(uint32_t), s));
  FQ_LAUNCH(flag_roots, n, s, n, f.grid.rank.data(), f.next.data(), flag);
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temp, bytes, flag, scan, int(n + 1), s));
  FQ_LAUNCH(label_kernel, n, s, n, f.grid.rank.data(), f.grid.order.data(), root, scan, labels);
  FQ_CUDA_CHECK(cudaMemcpyAsync(labels + n, scan + n, sizeof(uint32_t), cudaMemcpyDeviceToDevice, s));
}

}  // namespace fq::cuda
