// The CUDA engine: the CPU engine's passes (cpu_engine.cpp) as kernels on persistent
// device buffers. The host stages the raw frame into pinned memory while it is uploaded;
// the device checks and normalizes it (frame_prep.h's math, frame_checks.cu), does every
// pass and maps the result back to input units; the host copies it out of pinned memory.
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/device_frame.cuh"
#include "kernels/cuda/frame_checks.cuh"
#include "kernels/cuda/host_staging.h"
#include "kernels/cuda/id_pass.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/link_export_pass.cuh"
#include "kernels/cuda/passes.cuh"
#include "kernels/cuda/refine_passes.cuh"
#include "kernels/cuda/stream.cuh"
#include "kernels/cuda/team_passes.cuh"
#include "kernels/cuda/temporal_pass.cuh"
#include "kernels/cuda_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"

namespace fq {

namespace {

std::atomic<uint64_t> g_allocations{0};
std::atomic<uint64_t> g_device_bytes{0};
std::atomic<bool> g_fail_next_launch{false};

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Selects the device before the stream and events (members below) are created on it.
struct DeviceSelection {
  explicit DeviceSelection(int device) : id(device) { FQ_CUDA_CHECK(cudaSetDevice(device)); }
  int id;
};

class CudaEngine final : public Engine {
 public:
  CudaEngine(int device, const CudaTuning& tuning) : device_(device), tuning_(tuning), events_(kMaxMarks) {
    cudaDeviceProp prop{};
    FQ_CUDA_CHECK(cudaGetDeviceProperties(&prop, device));
    name_ = std::string("cuda:") + prop.name;
    sm_count_ = prop.multiProcessorCount;
  }
  std::string name() const override { return name_; }
  Status run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) override;
  void temporal_step(const MeshView& mesh, const Params& params, FrameResult& out) override;
  Status average_ids(const MeshView& mesh, uint64_t fingerprint, float strength, std::vector<float>& averaged,
                     IdStep& step) override;
  void release_scratch() override;

 private:
  static constexpr int kMaxMarks = 16;
  static constexpr int kDownloadChunks = 8;  ///< most chunks of one download
  Status run_frame(const MeshView& mesh, const RunPlan& run, FrameResult& out);
  void upload(const MeshView& mesh);
  Status normalize(const MeshView& mesh, float cell, Normalization& norm);
  Status enqueue_passes(const RunPlan& run, FrameResult& out);
  /// One pass of `run` (the passes before it enqueued); reads the noise estimate back for kRefine.
  void enqueue_pass(PassKind pass, const RunPlan& run, FrameResult& out);
  Status mark(const char* pass);
  Status stop_if_cancelled();
  int team_size() const;
  Status fail(const std::string& what, FrameResult& out);

  DeviceSelection device_;
  CudaTuning tuning_;
  cuda::Stream stream_;
  cuda::PassEvents events_;
  cuda::SyncEvents downloads_{2 * kDownloadChunks};
  cuda::DeviceFrame f_;
  cuda::RefineBuffers refine_;
  cuda::TemporalPass temporal_;    ///< the temporal step, and the device copies of histories it wrote
  cuda::IdPass ids_;               ///< track A's step, and its device copies of tables and averages
  bool temporal_pending_ = false;  ///< the frame's own run took the step: temporal_step() finishes it
  std::string name_;
  int sm_count_ = 1;
  bool usable_ = true;
  std::string fault_;
};

Status CudaEngine::run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  if (Status st = check_mesh_counts(mesh); !st.ok()) return st;
  if (!usable_)
    return {StatusCode::kInternal, "the CUDA engine is unusable after an earlier device fault: " + fault_};
  try {
    return run_frame(mesh, run, out);
  } catch (const cuda::CudaError& e) {
    return fail(e.what(), out);
  } catch (const std::bad_alloc&) {
    return fail("out of host memory (pinned staging)", out);
  }
}

// The device step ran in the frame's own run (run_frame); the stream's history takes the
// result here, once Engine::process has seen the frame through (a stopped frame's result
// must not become the history).
void CudaEngine::temporal_step(const MeshView&, const Params& params, FrameResult& out) {
  if (!temporal_pending_ || !follows_history(params)) return;
  temporal_pending_ = false;
  const Clock::time_point t = Clock::now();
  report_step(temporal_.finish(out.positions, out.mean_edge, *history_), out);
  out.timings.push_back({"temporal_host", ms_since(t)});
}

// Track A's per-vertex math on the device (kernels/cuda/id_pass.cuh); the host keeps the
// stream's state, so the next frame may go to any engine.
Status CudaEngine::average_ids(const MeshView& mesh, uint64_t fingerprint, float strength,
                               std::vector<float>& averaged, IdStep& step) {
  if (!usable_)
    return {StatusCode::kInternal, "the CUDA engine is unusable after an earlier device fault: " + fault_};
  FrameResult none;
  try {
    FQ_CUDA_CHECK(cudaSetDevice(device_.id));
    step = ids_.step(mesh, fingerprint, history_->mean_edge, strength, history_->ids, averaged,
                     temporal_scratch_, host_threads(), stream_.get());
    return {};
  } catch (const cuda::CudaError& e) {
    return fail(e.what(), none);
  } catch (const std::bad_alloc&) {
    return fail("out of host memory (pinned staging)", none);
  }
}

void CudaEngine::release_scratch() {
  // The frees must be made on this engine's device; the destructors log a failed free.
  if (cudaSetDevice(device_.id) != cudaSuccess) {
    (void)cudaGetLastError();
    return;
  }
  f_ = cuda::DeviceFrame{};
  refine_ = cuda::RefineBuffers{};
  temporal_ = cuda::TemporalPass{};
  ids_ = cuda::IdPass{};
  temporal_pending_ = false;
}

// A bad launch is cleared by reading it; a fault inside a kernel is sticky and leaves the
// context unusable, which the synchronization below reveals.
Status CudaEngine::fail(const std::string& what, FrameResult& out) {
  out.timings.clear();
  out.labels.clear();
  out.num_clusters = 0;
  (void)cudaGetLastError();
  const cudaError_t sync = cudaStreamSynchronize(stream_.get());
  std::string msg = "CUDA error on this frame: " + what;
  if (sync != cudaSuccess) {
    usable_ = false;
    fault_ = std::string(cudaGetErrorName(sync)) + " (" + cudaGetErrorString(sync) + ")";
    msg += "; the device context is lost (" + fault_ + "), this engine cannot process further frames";
  }
  return {StatusCode::kInternal, msg};
}

// The raw frame, coordinates then indices, through one pinned staging buffer.
void CudaEngine::upload(const MeshView& mesh) {
  const size_t coord_bytes = 3 * size_t(f_.n) * sizeof(float);
  const size_t index_bytes = 3 * size_t(f_.m) * sizeof(uint32_t);
  unsigned char* staging = f_.h_upload.reserve(coord_bytes + index_bytes);
  const cudaStream_t s = stream_.get();
  cuda::upload_staged(mesh.positions, f_.in_coords.reserve(3 * size_t(f_.n)), coord_bytes, staging, s);
  cuda::upload_staged(mesh.triangles, f_.in_tris.reserve(3 * size_t(f_.m)), index_bytes,
                      staging + coord_bytes, s);
}

// The device's checks read back (the one synchronization inside a frame: the grid layout
// is chosen on the host, as build_grid does), judged by frame_prep.h's functions, so a bad
// frame gets the CPU engine's message; then the points are normalized on the device.
Status CudaEngine::normalize(const MeshView& mesh, float cell, Normalization& norm) {
  const cudaStream_t s = stream_.get();
  cuda::reduce_frame(f_, s);
  events_.mark("checks", s);
  stream_.sync();
  const cuda::FrameSummary sum = cuda::read_summary(f_);
  if (Status st = mesh_faults(mesh, sum.bad_coordinate, sum.bad_index); !st.ok()) return st;
  if (Status st = normalization_from(sum.lo, sum.hi, sum.mean_edge, norm); !st.ok()) return st;
  // The map is monotonic in each coordinate, so the normalized bounds are the bounds mapped.
  const float lo_in[3] = {float(sum.lo[0]), float(sum.lo[1]), float(sum.lo[2])};
  const float hi_in[3] = {float(sum.hi[0]), float(sum.hi[1]), float(sum.hi[2])};
  f_.grid.layout = choose_grid_layout(norm.to_normalized(lo_in), norm.to_normalized(hi_in), cell, f_.n);
  cuda::normalize_points(f_, norm, s);
  events_.mark("to_normalized", s);
  return {};
}

// With a cancel token, the host keeps at most one pass queued behind the one running: after
// enqueuing a pass it waits (checking the token) for the pass before it to end, so the device
// always has the next pass. A cancelled frame stops within the two passes in flight, which are
// left to finish (a kernel cannot be interrupted) before the stream is free again. Only after a
// pass of over 2 ms does the host wait in 0.1 ms naps, and a following pass shorter than a nap
// may then leave the device idle until the host wakes. Measured on an H100 host (fqbench
// --cancel-token): no change for bunny and igea; igea_x16 frame wall +1 ms (5%) with 1 ms naps.
Status CudaEngine::mark(const char* pass) {
  const cudaStream_t s = stream_.get();
  events_.mark(pass, s);
  if (cancel_ == nullptr) return {};
  const cudaEvent_t previous = events_.recent(1);
  const Clock::time_point spin_until = Clock::now() + std::chrono::milliseconds(2);
  for (;;) {
    const cudaError_t q = cudaEventQuery(previous);
    if (q == cudaSuccess || cancel_->expired()) break;
    if (q != cudaErrorNotReady) FQ_CUDA_CHECK(q);
    // Short passes are waited for by spinning (as cudaEventSynchronize does); long ones in
    // 0.1 ms naps.
    if (Clock::now() > spin_until) std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  return stop_if_cancelled();
}

// A cancelled frame returns once the device is done with what was queued: the next frame
// may free or reuse the buffers at once.
Status CudaEngine::stop_if_cancelled() {
  Status st = check_cancel();
  if (!st.ok()) stream_.sync();
  return st;
}

// Lanes per vertex in the neighbourhood passes, from vertices per SM. Measured on the H100
// (docs/BENCHMARKS.md, sweep of the team size): small meshes need lanes to fill the GPU
// (bunny: 8 lanes 0.31 ms, 1 lane 0.72 ms); up to ~1.6M vertices 4 lanes still win by
// making the row loop uniform (dragon 1.90 vs 2.34 ms); above that one thread per vertex
// is best (igea_x16 7.49 ms vs 7.74 with 4). CudaTuning::team overrides it.
int CudaEngine::team_size() const {
  if (tuning_.team != CudaTuning::kTeamBySize) return tuning_.team;
  const uint64_t per_sm = f_.n / uint64_t(sm_count_ > 0 ? sm_count_ : 1);
  return per_sm <= 512 ? 8 : (per_sm <= 12288 ? 4 : 1);
}

Status CudaEngine::enqueue_passes(const RunPlan& run, FrameResult& out) {
  for (PassKind pass : run.passes) {
    if (pass == PassKind::kGrid) {
      cuda::sort_into_grid(f_, f_.grid.layout, stream_.get());
    } else {
      enqueue_pass(pass, run, out);
    }
    FQ_RETURN_IF_ERROR(mark(pass_name(pass)));
  }
  return {};
}

void CudaEngine::enqueue_pass(PassKind pass, const RunPlan& run, FrameResult& out) {
  const cudaStream_t s = stream_.get();
  const int team = team_size();
  const bool fast_exp = tuning_.fast_exp;
  switch (pass) {
    case PassKind::kGrid:
      break;  // needs the layout: enqueue_passes
    case PassKind::kBaseQuadrics:
      cuda::base_quadrics(f_, s);
      break;  // also the vertex -> triangle table "qf+" reads
    // The team kernels, or with team 0 the one-thread-per-vertex ones.
    case PassKind::kNeighbourhoodQuadrics:
      team ? cuda::team_neighbourhood_quadrics(f_, run.sigma_b, team, fast_exp, s)
           : cuda::neighbourhood_quadrics(f_, run.sigma_b, s);
      break;
    case PassKind::kDiffusion:
      team ? cuda::team_diffuse_quadrics(f_, run, team, fast_exp, s) : cuda::diffuse_quadrics(f_, run, s);
      break;
    case PassKind::kNoise: {
      const NoiseEstimate e = cuda::estimate_noise(f_, refine_, s);
      out.keep(e);
      break;
    }
    case PassKind::kRefine: {
      const RefinePlan plan = run.refinement(out.estimate());
      cuda::refine_positions(f_, refine_, plan, s);
      out.filter_noise = plan.noise;
      break;
    }
    case PassKind::kUpdate:
      cuda::update_positions(f_, run, s);
      break;
    case PassKind::kBilateralFilter:
      cuda::bilateral_filter(f_, run, s);
      break;
    case PassKind::kScore:
      team ? cuda::team_cluster_scores(f_, run, team, fast_exp, s) : cuda::cluster_scores(f_, run, s);
      break;
    case PassKind::kLink:
      team ? cuda::team_cluster_links(f_, run, team, fast_exp, s) : cuda::cluster_links(f_, run, s);
      break;
    case PassKind::kModes:
      cuda::cluster_labels(f_, s);
      break;
    case PassKind::kExportLinks:
      cuda::export_links(f_, run.params.clustering, s);
      break;  // downloads too
  }
}

Status CudaEngine::run_frame(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  const Params& params = run.params;
  if (run.role == RunRole::kFrame) temporal_pending_ = false;  // a stopped frame's step is dropped
  FQ_CUDA_CHECK(cudaSetDevice(device_.id));
  const cudaStream_t s = stream_.get();
  // A frame far smaller than the largest one so far gives that one's buffers back.
  if (far_smaller(mesh.num_vertices, f_.points.capacity())) release_scratch();
  f_.n = mesh.num_vertices;
  f_.m = mesh.num_triangles;
  const uint32_t n = f_.n;

  events_.begin(s);
  upload(mesh);
  events_.mark("upload", s);
  Normalization norm;
  if (Status st = normalize(mesh, run.grid_cell, norm); !st.ok()) return st;
  out.mean_edge = norm.mean_edge;
  FQ_RETURN_IF_ERROR(stop_if_cancelled());
  FQ_RETURN_IF_ERROR(enqueue_passes(run, out));
  // The temporal step (kernels/cuda/temporal_pass.cuh) on the frame's own result, before it
  // leaves the device; temporal_step() hands it to the history once the frame is through.
  const bool temporal = run.role == RunRole::kFrame && follows_history(params);
  if (temporal) {
    temporal_.follow(f_, norm, *history_, params.filtering.temporal, out.noise_estimate, s);
    FQ_RETURN_IF_ERROR(mark("temporal"));
  }
  if (params.filter) {
    cuda::positions_to_input(f_, norm, s);
    FQ_RETURN_IF_ERROR(mark("output"));
  }
  // Results come down in chunks, each copied out of pinned memory while the next is in flight.
  const int half = downloads_.size() / 2;
  cuda::StagedDownload positions, labels;
  if (params.filter) {
    const size_t bytes = 3 * size_t(n) * sizeof(float);
    out.positions.resize(3 * size_t(n));
    positions = cuda::enqueue_download(f_.out_coords.data(), out.positions.data(), bytes,
                                       f_.h_download.reserve(bytes), downloads_.data(), half, s);
  }
  if (params.cluster) {
    const size_t bytes = size_t(n) * sizeof(uint32_t);
    uint32_t* staging = f_.h_labels.reserve(n + 1);
    out.labels.resize(n);
    labels =
        cuda::enqueue_download(f_.labels.data(), out.labels.data(), bytes,
                               reinterpret_cast<unsigned char*>(staging), downloads_.data() + half, half, s);
    FQ_CUDA_CHECK(
        cudaMemcpyAsync(staging + n, f_.labels.data() + n, sizeof(uint32_t), cudaMemcpyDeviceToHost, s));
  }
  if (temporal) temporal_.keep(f_, s);
  events_.mark("download", s);
  if (!params.filter) {  // the input positions, copied while the device works
    out.positions.resize(3 * size_t(n));
    cuda::parallel_copy(out.positions.data(), mesh.positions, 3 * size_t(n) * sizeof(float));
  }
  const cuda::StagedDownload& first = params.filter ? positions : labels;
  if (first.done) FQ_CUDA_CHECK(cudaEventSynchronize(first.done[0]));
  const Clock::time_point t1 = Clock::now();
  if (params.filter) cuda::complete_download(positions);
  if (params.cluster) cuda::complete_download(labels);
  stream_.sync();
  if (params.cluster) {
    out.num_clusters = f_.h_labels.data()[n];
    out.theta = params.clustering.theta;
  }
  if (params.cluster && params.clustering.keep_links) {  // downloaded by export_links on the stream
    out.link_parent.assign(f_.h_link_parent.data(), f_.h_link_parent.data() + n);
    out.link_p.assign(f_.h_link_p.data(), f_.h_link_p.data() + n);
  }
  events_.collect([&](const char* name, double ms) { out.timings.push_back({name, ms}); });
  // Host: results out of pinned memory from the first downloaded chunk on (overlaps the download).
  out.timings.push_back({"finish", ms_since(t1)});
  temporal_pending_ = temporal;
  return {};
}

}  // namespace

namespace cuda {

void note_device_allocation(size_t bytes) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  g_device_bytes.fetch_add(bytes, std::memory_order_relaxed);
}

void note_device_free(size_t bytes) { g_device_bytes.fetch_sub(bytes, std::memory_order_relaxed); }

unsigned block_size() {
  static const unsigned size = [] {
    const char* env = std::getenv("FQ_CUDA_BLOCK");
    const long v = env ? std::strtol(env, nullptr, 10) : 0;
    return v >= 32 && v <= 1024 && v % 32 == 0 ? static_cast<unsigned>(v) : tuning::kItemBlock;
  }();
  return size;
}

unsigned grid_size(uint64_t items, uint64_t per_block) {
  if (g_fail_next_launch.exchange(false)) return 0;
  const uint64_t b = (items + per_block - 1) / per_block;
  if (b > tuning::kMaxGrid) return 0;
  return b > 0 ? static_cast<unsigned>(b) : 1u;
}

void fail_next_launch() { g_fail_next_launch.store(true); }

uint64_t resident_blocks(const void* kernel, unsigned threads, const char* name, const char* file, int line) {
  struct Known {
    const void* kernel;
    int device;
    unsigned threads;
    uint64_t blocks;
  };
  static std::mutex lock;
  static std::vector<Known> known;  // a few cooperative kernels times the devices: a short list
  int device = 0;
  check(cudaGetDevice(&device), name, file, line);
  {
    const std::lock_guard<std::mutex> hold(lock);
    for (const Known& k : known)
      if (k.kernel == kernel && k.device == device && k.threads == threads) return k.blocks;
  }
  int sms = 0, per_sm = 0;
  check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), name, file, line);
  check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, kernel, int(threads), 0), name, file, line);
  const uint64_t blocks = uint64_t(per_sm) * uint64_t(sms);
  const std::lock_guard<std::mutex> hold(lock);
  known.push_back({kernel, device, threads, blocks});  // a race may add a twin: the same value
  return blocks;
}

}  // namespace cuda

uint64_t cuda_allocation_count() { return g_allocations.load(std::memory_order_relaxed); }

uint64_t cuda_device_bytes_held() { return g_device_bytes.load(std::memory_order_relaxed); }

void cuda_fail_next_launch_for_testing() { cuda::fail_next_launch(); }

std::unique_ptr<Engine> make_cuda_engine(int device, Status* why, const CudaTuning& tuning) {
  auto unavailable = [&](std::string msg) -> std::unique_ptr<Engine> {
    (void)cudaGetLastError();
    if (why) *why = {StatusCode::kUnavailable, std::move(msg)};
    return nullptr;
  };
  if (!valid_cuda_team(tuning.team)) {
    if (why)
      *why = invalid_argument("CUDA team size " + std::to_string(tuning.team) +
                              " is not one of 0, 1, 2, 4, 8, 16, 32");
    return nullptr;
  }
  int count = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&count); e != cudaSuccess)
    return unavailable(std::string("no usable CUDA device: ") + cudaGetErrorName(e) + " (" +
                       cudaGetErrorString(e) + ")");
  if (count == 0) return unavailable("no CUDA device is present");
  if (device < 0 || device >= count)
    return unavailable("CUDA device " + std::to_string(device) + " does not exist (" + std::to_string(count) +
                       " present)");
  try {
    auto engine = std::make_unique<CudaEngine>(device, tuning);
    if (why) *why = {};
    return engine;
  } catch (const cuda::CudaError& e) {
    return unavailable("could not start the CUDA engine on device " + std::to_string(device) + ": " +
                       e.what());
  }
}

}  // namespace fq
