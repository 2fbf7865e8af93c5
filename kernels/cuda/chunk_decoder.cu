// ChunkDecoder: the plan, the packed bytes through pinned memory, the kernel, the faults back.
#include <cuda_runtime.h>

#include <cstring>
#include <string>

#include "kernels/cuda/chunk_decode.cuh"
#include "kernels/cuda/chunk_decoder.h"
#include "kernels/cuda/device_buffer.cuh"
#include "kernels/cuda/stream.cuh"

namespace fq::cuda {

struct ChunkDecoder::Device {
  explicit Device(ChunkTeam t) : team(t), events(3) {}
  ChunkTeam team;
  ChunkPlan plan;
  ChunkDecodeTimes times;
  Stream stream;
  PassEvents events;
  PinnedBuffer<uint8_t> staged_bytes;
  PinnedBuffer<ChunkJob> staged_jobs;
  PinnedBuffer<uint32_t> staged_faults;
  DeviceBuffer<uint8_t> bytes;
  DeviceBuffer<ChunkJob> jobs;
  DeviceBuffer<wire::detail::RansSymbol> symbols;
  DeviceBuffer<uint32_t> buckets, corners, labels, faults;
  DeviceBuffer<int32_t> values;
  DeviceBuffer<float> positions;

  /// Room for the plan's outputs (grow-only) and the kernel's arguments.
  ChunkDecodeArgs reserve() {
    const size_t chunks = plan.jobs.size();
    ChunkDecodeArgs a;
    a.bytes = bytes.reserve(plan.bytes);
    a.jobs = jobs.reserve(chunks);
    a.chunks = static_cast<uint32_t>(chunks);
    a.symbols = symbols.reserve(plan.symbols);
    if (team == ChunkTeam::kThread) a.buckets = buckets.reserve(chunks * wire::detail::kRansBuckets);
    a.values = values.reserve(3 * plan.points);
    a.positions = positions.reserve(3 * plan.points);
    a.corners = corners.reserve(plan.corners);
    a.labels = plan.labelled ? labels.reserve(plan.points) : labels.data();
    a.faults = faults.reserve(chunks);
    staged_bytes.reserve(plan.bytes);
    staged_jobs.reserve(chunks);
    staged_faults.reserve(chunks);
    return a;
  }
};

ChunkDecoder::ChunkDecoder(ChunkTeam team) : d_(std::make_unique<Device>(team)) {}
ChunkDecoder::~ChunkDecoder() = default;

fq::Status ChunkDecoder::decode(const std::vector<std::string_view>& chunks, uint32_t id_limit) {
  Device& d = *d_;
  FQ_RETURN_IF_ERROR(plan_chunks(chunks, id_limit, d.plan));
  const ChunkDecodeArgs a = d.reserve();
  const size_t count = chunks.size();
  for (size_t i = 0; i < count; ++i)
    std::memcpy(d.staged_bytes.data() + d.plan.jobs[i].bytes_at, chunks[i].data(), chunks[i].size());
  std::memcpy(d.staged_jobs.data(), d.plan.jobs.data(), count * sizeof(ChunkJob));
  const cudaStream_t s = d.stream.get();
  d.events.begin(s);
  FQ_CUDA_CHECK(
      cudaMemcpyAsync(d.bytes.data(), d.staged_bytes.data(), d.plan.bytes, cudaMemcpyHostToDevice, s));
  FQ_CUDA_CHECK(cudaMemcpyAsync(d.jobs.data(), d.staged_jobs.data(), count * sizeof(ChunkJob),
                                cudaMemcpyHostToDevice, s));
  d.events.mark("upload", s);
  launch_chunk_decode(a, d.team, s);
  d.events.mark("kernel", s);
  FQ_CUDA_CHECK(
      cudaMemcpyAsync(d.staged_faults.data(), a.faults, count * sizeof(uint32_t), cudaMemcpyDeviceToHost, s));
  d.stream.sync();
  d.events.collect([&](const char* name, double ms) {
    (std::strcmp(name, "upload") == 0 ? d.times.upload_ms : d.times.kernel_ms) = ms;
  });
  for (size_t i = 0; i < count; ++i) {
    if (const uint32_t f = d.staged_faults.data()[i]; f != kChunkDecoded)
      return invalid_input("chunk " + std::to_string(i) + ": " + chunk_fault_name(f));
  }
  return {};
}

const ChunkPlan& ChunkDecoder::plan() const { return d_->plan; }
const ChunkDecodeTimes& ChunkDecoder::times() const { return d_->times; }
const float* ChunkDecoder::device_positions() const { return d_->positions.data(); }
const uint32_t* ChunkDecoder::device_corners() const { return d_->corners.data(); }
const uint32_t* ChunkDecoder::device_labels() const { return d_->labels.data(); }

void ChunkDecoder::download(std::vector<float>& positions, std::vector<uint32_t>& corners,
                            std::vector<uint32_t>& labels) const {
  const ChunkPlan& p = d_->plan;
  positions.resize(3 * p.points);
  corners.resize(p.corners);
  labels.resize(p.labelled ? p.points : 0);
  FQ_CUDA_CHECK(cudaMemcpy(positions.data(), d_->positions.data(), positions.size() * sizeof(float),
                           cudaMemcpyDeviceToHost));
  FQ_CUDA_CHECK(cudaMemcpy(corners.data(), d_->corners.data(), corners.size() * sizeof(uint32_t),
                           cudaMemcpyDeviceToHost));
  if (!labels.empty())
    FQ_CUDA_CHECK(cudaMemcpy(labels.data(), d_->labels.data(), labels.size() * sizeof(uint32_t),
                             cudaMemcpyDeviceToHost));
}

fq::Status chunk_decoder_device() {
  int count = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&count); e != cudaSuccess)
    return {StatusCode::kUnavailable, std::string("no usable CUDA device: ") + cudaGetErrorName(e)};
  if (count == 0) return {StatusCode::kUnavailable, "no CUDA device is present"};
  return {};
}

}  // namespace fq::cuda
