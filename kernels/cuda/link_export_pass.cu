#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/link_export_pass.cuh"
#include "kernels/link_export.h"

namespace fq::cuda {

namespace {

__global__ void export_links_kernel(uint32_t n, const Point4* points, const Quadric* bl, const uint32_t* next,
                                    const uint32_t* order, const uint32_t* rank, Gaussian gd, Gaussian gq,
                                    bool euclid, uint32_t* parent, float* p) {
  const uint64_t i = item_index();
  if (i < n) export_link(points, bl, next, order, rank[i], gd, gq, euclid, parent[i], p[i]);
}

}  // namespace

void export_links(DeviceFrame& f, const ClusterParams& p, cudaStream_t s) {
  const uint32_t n = f.n;
  uint32_t* parent = f.link_parent.reserve(n);
  float* prox = f.link_p.reserve(n);
  FQ_LAUNCH(export_links_kernel, n, s, n, f.points.data(), f.bl.data(), f.next.data(), f.grid.order.data(),
            f.grid.rank.data(), Gaussian::with_sigma(p.sigma_d), Gaussian::with_sigma(p.sigma_q),
            p.method == ClusterMethod::kEuclidean, parent, prox);
  FQ_CUDA_CHECK(
      cudaMemcpyAsync(f.h_link_parent.reserve(n), parent, n * sizeof(uint32_t), cudaMemcpyDeviceToHost, s));
  FQ_CUDA_CHECK(cudaMemcpyAsync(f.h_link_p.reserve(n), prox, n * sizeof(float), cudaMemcpyDeviceToHost, s));
}

}  // namespace fq::cuda
