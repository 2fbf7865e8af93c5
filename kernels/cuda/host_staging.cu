#include "kernels/cuda/host_staging.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/parallel_for.h"

namespace fq::cuda {

namespace {

// A transfer chunk is large enough that each cudaMemcpyAsync runs near the link's rate and
// small enough that the first one starts early; a piece is one thread's share of a chunk.
constexpr size_t kChunk = size_t(8) << 20;
constexpr size_t kPiece = size_t(512) << 10;

size_t pieces_of(size_t bytes) { return (bytes + kPiece - 1) / kPiece; }

void copy_piece(unsigned char* dst, const unsigned char* src, size_t bytes, size_t p) {
  const size_t begin = p * kPiece;
  std::memcpy(dst + begin, src + begin, std::min(kPiece, bytes - begin));
}

}  // namespace

void upload_staged(const void* src, void* dst, size_t bytes, unsigned char* staging, cudaStream_t s) {
  const auto* in = static_cast<const unsigned char*>(src);
  auto* out = static_cast<unsigned char*>(dst);
  const int64_t chunks = static_cast<int64_t>((bytes + kChunk - 1) / kChunk);
  // Exceptions cannot leave a parallel region: the first failed enqueue is kept and thrown after.
  cudaError_t failed = cudaSuccess;
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel num_threads(hardware_threads())
#endif
  for (int64_t c = 0; c < chunks; ++c) {
    const size_t begin = size_t(c) * kChunk, len = std::min(kChunk, bytes - begin);
    const int64_t pieces = static_cast<int64_t>(pieces_of(len));
#if defined(FQ_HAVE_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int64_t p = 0; p < pieces; ++p) copy_piece(staging + begin, in + begin, len, size_t(p));
    // The loop's barrier has passed: chunk c is staged. The calling thread (which holds the
    // engine's device) enqueues it while the others go on to chunk c + 1.
#if defined(FQ_HAVE_OPENMP)
#pragma omp master
#endif
    {
      const cudaError_t e = cudaMemcpyAsync(out + begin, staging + begin, len, cudaMemcpyHostToDevice, s);
      if (e != cudaSuccess && failed == cudaSuccess) failed = e;
    }
  }
  check(failed, "cudaMemcpyAsync (staged upload)", __FILE__, __LINE__);
}

void parallel_copy(void* dst, const void* src, size_t bytes) {
  const auto* in = static_cast<const unsigned char*>(src);
  auto* out = static_cast<unsigned char*>(dst);
  const int64_t pieces = static_cast<int64_t>(pieces_of(bytes));
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel for schedule(static) num_threads(hardware_threads())
#endif
  for (int64_t p = 0; p < pieces; ++p) copy_piece(out, in, bytes, size_t(p));
}

}  // namespace fq::cuda
