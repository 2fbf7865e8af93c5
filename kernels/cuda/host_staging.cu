#include <algorithm>
#include <cstdint>
#include <cstring>

#include "kernels/cuda/host_staging.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "common/thread_pool.h"
#include "core/parallel_for.h"
#include "kernels/cuda/cuda_check.cuh"

namespace fq::cuda {

namespace {

// A transfer chunk is large enough that each cudaMemcpyAsync runs near the link's rate and
// small enough that the first one starts early; a piece is one thread's share of a chunk.
constexpr size_t kChunk = size_t(4) << 20;
constexpr size_t kPiece = size_t(256) << 10;

size_t pieces_of(size_t bytes) { return (bytes + kPiece - 1) / kPiece; }

// Threads of a staging team. A few saturate the copy to pinned memory; a team as wide as the
// machine waits at every chunk's barrier for its slowest member, and in fqd the codec pool and
// the other stages keep every core busy: on an H100 host (16 cores) igea at 30 fps showed
// upload p95 22 ms for a p50 of 0.3 ms with 16 staging threads.
int staging_threads() { return std::min(4, hardware_threads()); }

// dst = src with streaming (non-temporal) stores where the CPU has them. glibc's memcpy
// switches to such stores only for copies of several MB, and a thread's piece here is
// 256 KB: with ordinary stores every destination line is first read for ownership, a
// third more memory traffic on the path that bounds a large frame's upload. Neither side
// reads the destination soon (the copy engine does, or the caller, later).
void stream_copy(unsigned char* dst, const unsigned char* src, size_t len) {
#if defined(__SSE2__)
  const size_t head = std::min(len, (16 - (reinterpret_cast<uintptr_t>(dst) & 15)) & 15);
  std::memcpy(dst, src, head);
  dst += head;
  src += head;
  len -= head;
  const size_t body = len / 64 * 64;
  for (size_t k = 0; k < body; k += 64) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + k));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + k + 16));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + k + 32));
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + k + 48));
    _mm_stream_si128(reinterpret_cast<__m128i*>(dst + k), a);
    _mm_stream_si128(reinterpret_cast<__m128i*>(dst + k + 16), b);
    _mm_stream_si128(reinterpret_cast<__m128i*>(dst + k + 32), c);
    _mm_stream_si128(reinterpret_cast<__m128i*>(dst + k + 48), d);
  }
  std::memcpy(dst + body, src + body, len - body);
  _mm_sfence();  // the stores are visible before the chunk is handed on
#else
  std::memcpy(dst, src, len);
#endif
}

// dst = src in pieces of kPiece on the caller and staging_threads() - 1 threads of fq's shared
// pool. Not OpenMP: its runtime spins between regions next to the codec pool (thread_pool.h
// says why fqd avoids it), and the pool charges its helpers' CPU time to the stage that
// started the copy (common/thread_cpu.h), which OpenMP's threads escaped. Not parallel_for:
// a frame's cancel token must not cut a copy short.
void copy_pieces(unsigned char* dst, const unsigned char* src, size_t bytes) {
  ThreadPool::shared().run(pieces_of(bytes), staging_threads(), [&](size_t first, size_t last, size_t) {
    for (size_t p = first; p < last; ++p) {
      const size_t begin = p * kPiece;
      stream_copy(dst + begin, src + begin, std::min(kPiece, bytes - begin));
    }
  });
}

}  // namespace

void upload_staged(const void* src, void* dst, size_t bytes, unsigned char* staging, cudaStream_t s) {
  const auto* in = static_cast<const unsigned char*>(src);
  auto* out = static_cast<unsigned char*>(dst);
  for (size_t begin = 0; begin < bytes; begin += kChunk) {
    const size_t len = std::min(kChunk, bytes - begin);
    copy_pieces(staging + begin, in + begin, len);
    // Chunk c is staged: the calling thread (which holds the engine's device) enqueues it
    // before staging chunk c + 1, so the link copies one chunk while the host stages the next.
    FQ_CUDA_CHECK(cudaMemcpyAsync(out + begin, staging + begin, len, cudaMemcpyHostToDevice, s));
  }
}

StagedDownload enqueue_download(const void* src, void* dst, size_t bytes, unsigned char* staging,
                                const cudaEvent_t* done, int events, cudaStream_t s) {
  const size_t per_event = (bytes + size_t(events) - 1) / size_t(events);
  const size_t chunk = std::max(kChunk, (per_event + kPiece - 1) / kPiece * kPiece);
  const auto* in = static_cast<const unsigned char*>(src);
  for (size_t begin = 0, k = 0; begin < bytes; begin += chunk, ++k) {
    FQ_CUDA_CHECK(cudaMemcpyAsync(staging + begin, in + begin, std::min(chunk, bytes - begin),
                                  cudaMemcpyDeviceToHost, s));
    FQ_CUDA_CHECK(cudaEventRecord(done[k], s));
  }
  return {staging, static_cast<unsigned char*>(dst), bytes, chunk, done};
}

void complete_download(const StagedDownload& d) {
  for (size_t begin = 0, k = 0; begin < d.bytes; begin += d.chunk, ++k) {
    FQ_CUDA_CHECK(cudaEventSynchronize(d.done[k]));
    copy_pieces(d.dst + begin, d.staging + begin, std::min(d.chunk, d.bytes - begin));
  }
}

void parallel_copy(void* dst, const void* src, size_t bytes) {
  copy_pieces(static_cast<unsigned char*>(dst), static_cast<const unsigned char*>(src), bytes);
}

}  // namespace fq::cuda
