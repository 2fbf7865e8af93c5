// The uniform grid on the device: counting sort of points into cells with atomics, a CUB
// scan for the cell offsets, then a per-cell sort by input index so that the order inside
// each cell is the CPU's stable counting-sort order (which fixes summation order and the
// tie-breaking of quick shift by sorted index).
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "kernels/cuda/device_buffer.cuh"
#include "kernels/grid.h"
#include "kernels/grid_build.h"
#include "kernels/vec3.h"

namespace fq::cuda {

/// Device arrays of one grid; grow-only, reused from frame to frame.
struct DeviceGrid {
  GridLayout layout{};
  uint32_t count = 0;
  DeviceBuffer<uint32_t> cell_of;     ///< per input point
  DeviceBuffer<uint32_t> slot;        ///< per input point: arrival order in its cell
  DeviceBuffer<uint32_t> cell_count;  ///< cells + 1
  DeviceBuffer<uint32_t> cell_start;  ///< cells + 1
  DeviceBuffer<uint32_t> scattered;   ///< order before the per-cell sort
  DeviceBuffer<uint32_t> order;       ///< sorted -> input index
  DeviceBuffer<uint32_t> rank;        ///< input -> sorted index
  DeviceBuffer<unsigned char> temp;   ///< CUB scratch

  /// View over `sorted` points (device pointers).
  GridView view(const Point4* sorted) const {
    return {layout.origin, layout.cell, layout.nx, layout.ny, layout.nz, cell_start.data(), sorted, count};
  }
};

/// Sorts n points (input order, device) into `layout`'s cells; writes grid.order,
/// grid.rank, grid.cell_start, and `sorted_out[k] = in[order[k]]` (w copied).
void build_device_grid(const GridLayout& layout, const Point4* in, uint32_t n, DeviceGrid& grid,
                       Point4* sorted_out, cudaStream_t s);

}  // namespace fq::cuda
