// The host reader's columns time read_sequential_chunk over the frame's chunks on 1 and on
// `host_threads` threads (the codec's shared pool, as decode_frame reads them). The device's
// columns are the kernel alone (events) in each of its forms (a block of 1024 or 256, a warp,
// a thread a chunk), the upload of the packed bytes, the host's checks before it (plan_chunks)
// and ChunkDecoder::decode as the caller sees it (checks, packing, upload, kernel, the faults
// back) in the default form. Every form is checked bit for bit against the host first.
#include "clients/fqbench/codec_device_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string_view>

#include "clients/common/frame_sender.h"
#include "clients/fqbench/bench_stats.h"
#include "io/mesh_io.h"
#include "kernels/cuda/chunk_decoder.h"
#include "wire/draco_sequential_read.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

namespace fq::bench {
namespace {

double median_of(const std::vector<double>& v) { return spread_of(v).median; }

double wall_ms(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The host reader over every chunk on `threads` threads; false when one is not taken.
bool host_read(const std::vector<std::string_view>& chunks, int threads,
               std::vector<wire::detail::SequentialChunk>& out) {
  std::vector<char> ok(chunks.size(), 0);
  wire::detail::for_each_chunk(chunks.size(), threads, [&](size_t i, size_t) {
    ok[i] = wire::detail::read_sequential_chunk(chunks[i], wire::kMaxAttributeValue, out[i]) ? 1 : 0;
  });
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

/// Whether the device's last decode equals the host reader's, bit for bit.
bool same_reading(const cuda::ChunkDecoder& dec, const std::vector<wire::detail::SequentialChunk>& host) {
  std::vector<float> positions;
  std::vector<uint32_t> corners, labels;
  dec.download(positions, corners, labels);
  for (size_t i = 0; i < host.size(); ++i) {
    const cuda::ChunkJob& job = dec.plan().jobs[i];
    if (std::memcmp(positions.data() + 3 * job.first_point, host[i].positions.data(),
                    host[i].positions.size() * sizeof(float)) != 0 ||
        std::memcmp(corners.data() + job.first_corner, host[i].corners.data(),
                    host[i].corners.size() * sizeof(uint32_t)) != 0)
      return false;
  }
  return true;
}

/// The kernel's forms, widest first; the first is ChunkDecoder's default.
constexpr cuda::ChunkTeam kForms[] = {cuda::ChunkTeam::kBlock, cuda::ChunkTeam::kWideBlock,
                                      cuda::ChunkTeam::kWarp, cuda::ChunkTeam::kThread};
constexpr size_t kFormCount = sizeof(kForms) / sizeof(kForms[0]);

struct Row {
  uint32_t chunks = 0;
  uint64_t points = 0, bytes = 0;
  std::vector<double> host1, host_n, host_n_cpu, upload, checks, decode;
  std::vector<double> kernel[kFormCount];
};

/// One chunk count: the frame encoded as fqpub encodes it, then `repeat` rounds of each way.
bool measure(const Mesh& mesh, uint32_t chunks, const CodecDeviceBenchOptions& o, Row& row) {
  client::FrameSpec spec;  // fqpub's settings: the sequential coder, 16-bit positions, no labels
  spec.chunks = chunks;
  std::vector<std::string> parts;
  if (!client::build_frame(mesh.view(), spec, 0, parts).ok()) return false;
  const std::vector<std::string_view> views(parts.begin() + 2, parts.end());
  row.chunks = static_cast<uint32_t>(views.size());
  for (const std::string_view v : views) row.bytes += v.size();
  std::vector<wire::detail::SequentialChunk> host(views.size());
  std::vector<std::unique_ptr<cuda::ChunkDecoder>> forms;
  for (const cuda::ChunkTeam team : kForms) forms.push_back(std::make_unique<cuda::ChunkDecoder>(team));
  cuda::ChunkPlan plan;
  // Warm: buffers sized, pages touched, kernels loaded; and the readings checked.
  bool ok = host_read(views, o.host_threads, host);
  for (auto& f : forms) ok = ok && f->decode(views, wire::kMaxAttributeValue).ok() && same_reading(*f, host);
  if (!ok) {
    std::fprintf(stderr, "fqbench: the device and the host reader differ on %u chunks\n", row.chunks);
    return false;
  }
  row.points = forms[0]->plan().points;
  for (int r = 0; r < o.repeat && ok; ++r) {
    row.host1.push_back(wall_ms([&] { ok = host_read(views, 1, host) && ok; }));
    time_step([&] { return host_read(views, o.host_threads, host); }, ok, row.host_n, row.host_n_cpu);
    row.checks.push_back(
        wall_ms([&] { ok = cuda::plan_chunks(views, wire::kMaxAttributeValue, plan).ok() && ok; }));
    row.decode.push_back(wall_ms([&] { ok = forms[0]->decode(views, wire::kMaxAttributeValue).ok() && ok; }));
    row.upload.push_back(forms[0]->times().upload_ms);
    row.kernel[0].push_back(forms[0]->times().kernel_ms);
    for (size_t f = 1; f < kFormCount; ++f) {
      ok = forms[f]->decode(views, wire::kMaxAttributeValue).ok() && ok;
      row.kernel[f].push_back(forms[f]->times().kernel_ms);
    }
  }
  return ok;
}

std::vector<uint32_t> chunk_counts(const CodecDeviceBenchOptions& o, uint32_t vertices) {
  std::vector<uint32_t> c = o.chunks;
  if (c.empty()) c = {client::auto_chunks(vertices), 1, 16, 64, 256};
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  return c;
}

void print(const CodecDeviceBenchOptions& o, const Mesh& m, const std::vector<Row>& rows) {
  std::printf(
      "\n%s (%u V, %u F), fqpub's encoding (Draco's sequential coder, 16-bit positions); median of %d\n\n",
      o.mesh.c_str(), m.num_vertices(), m.num_triangles(), o.repeat);
  std::printf(
      "| chunks | points a chunk | KB | host 1 thread ms | host %d threads ms (CPU ms) | kernel ms: 256 a "
      "chunk "
      "| 1024 | 32 | 1 | µs a chunk (256) | upload ms | host checks ms | decode() ms (256) |\n"
      "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
      o.host_threads);
  for (const Row& r : rows) {
    std::printf("| %u | %llu | %.0f | %.2f | %.2f (%.2f) |", r.chunks,
                static_cast<unsigned long long>(r.points / r.chunks), double(r.bytes) / 1024.0,
                median_of(r.host1), median_of(r.host_n), median_of(r.host_n_cpu));
    for (const std::vector<double>& k : r.kernel) std::printf(" %.3f |", median_of(k));
    std::printf(" %.1f | %.3f | %.3f | %.3f |\n", 1e3 * median_of(r.kernel[0]) / r.chunks,
                median_of(r.upload), median_of(r.checks), median_of(r.decode));
  }
}

}  // namespace

int run_codec_device_bench(const CodecDeviceBenchOptions& o) {
  if (const Status s = cuda::chunk_decoder_device(); !s.ok()) {
    std::fprintf(stderr, "fqbench: %s\n", s.message().c_str());
    return 3;
  }
  Mesh mesh;
  const std::string path = std::filesystem::exists(o.mesh) ? o.mesh : o.mesh_dir + "/" + o.mesh;
  if (const Status st = io::read_mesh(path, mesh); !st.ok()) {
    std::fprintf(stderr, "fqbench: %s: %s\n", path.c_str(), st.message().c_str());
    return 1;
  }
  std::vector<Row> rows;
  for (const uint32_t chunks : chunk_counts(o, mesh.num_vertices())) {
    rows.emplace_back();
    if (!measure(mesh, chunks, o, rows.back())) return 1;
  }
  print(o, mesh, rows);
  return 0;
}

}  // namespace fq::bench
