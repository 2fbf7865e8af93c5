#include <algorithm>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_segmented_sort.cuh>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/device_grid.cuh"
#include "kernels/cuda/launch.cuh"

namespace fq::cuda {

namespace {

__global__ void count_cells(GridView shape, const Point4* in, uint32_t n, uint32_t* cell_of, uint32_t* slot,
                            uint32_t* cell_count) {
  const uint64_t i = item_index();
  if (i >= n) return;
  const uint32_t c = cell_index(shape, xyz(in[i]));
  cell_of[i] = c;
  slot[i] = atomicAdd(&cell_count[c], 1u);
}

__global__ void scatter_to_cells(uint32_t n, const uint32_t* cell_of, const uint32_t* slot,
                                 const uint32_t* cell_start, uint32_t* scattered) {
  const uint64_t i = item_index();
  if (i >= n) return;
  scattered[cell_start[cell_of[i]] + slot[i]] = i;
}

__global__ void permute_points(uint32_t n, const uint32_t* order, const Point4* in, Point4* sorted,
                               uint32_t* rank) {
  const uint64_t k = item_index();
  if (k >= n) return;
  const uint32_t i = order[k];
  rank[i] = k;
  sorted[k] = in[i];
}

}  // namespace

void build_device_grid(const GridLayout& layout, const Point4* in, uint32_t n, DeviceGrid& g,
                       Point4* sorted_out, cudaStream_t s) {
  g.layout = layout;
  g.count = n;
  const size_t cells = layout.cells();
  const GridView shape{layout.origin, layout.cell, layout.nx, layout.ny, layout.nz, nullptr, nullptr, n};
  g.cell_of.reserve(n);
  g.slot.reserve(n);
  g.scattered.reserve(n);
  g.order.reserve(n);
  g.rank.reserve(n);
  uint32_t* count = g.cell_count.reserve(cells + 1);
  uint32_t* start = g.cell_start.reserve(cells + 1);

  // Scratch for both CUB calls, sized before anything runs so that it grows at most once.
  size_t scan_bytes = 0, sort_bytes = 0;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes, count, start, int(cells + 1), s));
  FQ_CUDA_CHECK(cub::DeviceSegmentedSort::SortKeys(nullptr, sort_bytes, g.scattered.data(), g.order.data(),
                                                   int(n), int(cells), start, start + 1, s));
  const size_t temp_bytes = std::max(scan_bytes, sort_bytes);
  g.temp.reserve(temp_bytes);

  FQ_CUDA_CHECK(cudaMemsetAsync(count, 0, (cells + 1) * sizeof(uint32_t), s));
  FQ_LAUNCH(count_cells, n, s, shape, in, n, g.cell_of.data(), g.slot.data(), count);
  size_t bytes = temp_bytes;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(g.temp.data(), bytes, count, start, int(cells + 1), s));
  FQ_LAUNCH(scatter_to_cells, n, s, n, g.cell_of.data(), g.slot.data(), start, g.scattered.data());
  // Atomics gave an arbitrary order inside each cell; input order makes it the CPU's.
  bytes = temp_bytes;
  FQ_CUDA_CHECK(cub::DeviceSegmentedSort::SortKeys(g.temp.data(), bytes, g.scattered.data(), g.order.data(),
                                                   int(n), int(cells), start, start + 1, s));
  FQ_LAUNCH(permute_points, n, s, n, g.order.data(), in, sorted_out, g.rank.data());
}

}  // namespace fq::cuda
