// The CUDA engine: the CPU engine's passes (cpu_engine.cpp) as kernels on persistent
// device buffers. The host validates and normalizes the frame (frame_prep.h) into pinned
// staging, the device does every pass, the host maps the result back to input units.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/device_frame.cuh"
#include "kernels/cuda/host_staging.h"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"
#include "kernels/cuda/refine_passes.cuh"
#include "kernels/cuda/stream.cuh"
#include "kernels/cuda/team_passes.cuh"
#include "kernels/cuda_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"

namespace fq {

namespace {

std::atomic<uint64_t> g_allocations{0};
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
  explicit CudaEngine(int device) : device_(device), events_(kMaxMarks) {
    cudaDeviceProp prop{};
    FQ_CUDA_CHECK(cudaGetDeviceProperties(&prop, device));
    name_ = std::string("cuda:") + prop.name;
    sm_count_ = prop.multiProcessorCount;
  }
  std::string name() const override { return name_; }
  Status process(const MeshView& mesh, const Params& params, FrameResult& out) override;

 private:
  static constexpr int kMaxMarks = 16;
  void run_frame(const MeshView& mesh, const Params& params, const Normalization& norm, FrameResult& out);
  GridLayout stage_input(const MeshView& mesh, const Normalization& norm, float cell);
  void enqueue_passes(const Params& params);
  int team_size() const;
  static bool gather_base_quadrics();
  static bool fast_exp_enabled();
  void finish_output(const MeshView& mesh, const Params& params, const Normalization& norm, FrameResult& out);
  Status fail(const std::string& what, FrameResult& out);

  DeviceSelection device_;
  cuda::Stream stream_;
  cuda::PassEvents events_;
  cuda::DeviceFrame f_;
  cuda::RefineBuffers refine_;
  std::string name_;
  int sm_count_ = 1;
  double normalize_ms_ = 0.0;
  bool usable_ = true;
  std::string fault_;
};

Status CudaEngine::process(const MeshView& mesh, const Params& params, FrameResult& out) {
  out.timings.clear();
  out.labels.clear();
  out.num_clusters = 0;
  if (Status s = validate(params); !s.ok()) return s;
  const Clock::time_point t0 = Clock::now();
  if (Status s = check_mesh(mesh); !s.ok()) return s;
  Normalization norm;
  if (Status s = compute_normalization(mesh, norm); !s.ok()) return s;
  out.mean_edge = norm.mean_edge;
  normalize_ms_ = ms_since(t0);
  if (!usable_)
    return {StatusCode::kInternal, "the CUDA engine is unusable after an earlier device fault: " + fault_};
  try {
    run_frame(mesh, params, norm, out);
  } catch (const cuda::CudaError& e) {
    return fail(e.what(), out);
  } catch (const std::bad_alloc&) {
    return fail("out of host memory (pinned staging)", out);
  }
  return {};
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

GridLayout CudaEngine::stage_input(const MeshView& mesh, const Normalization& norm, float cell) {
  const uint32_t n = mesh.num_vertices, m = mesh.num_triangles;
  f_.n = n;
  f_.m = m;
  Vec3 lo, hi;
  cuda::stage_points(mesh, norm, f_.h_points.reserve(n), lo, hi);
  cuda::copy_indices(mesh.triangles, f_.h_tris.reserve(3 * size_t(m)), 3 * size_t(m));
  return choose_grid_layout(lo, hi, cell, n);  // as build_grid on the CPU
}

// Lanes per vertex in the neighbourhood passes, from vertices per SM. Measured on the H100
// (docs/BENCHMARKS.md, sweep of FQ_CUDA_TEAM): small meshes need lanes to fill the GPU
// (bunny: 8 lanes 0.31 ms, 1 lane 0.72 ms); up to ~1.6M vertices 4 lanes still win by
// making the row loop uniform (dragon 1.90 vs 2.34 ms); above that one thread per vertex
// is best (igea_x16 7.49 ms vs 7.74 with 4). FQ_CUDA_TEAM overrides it: 0 selects the
// one-thread-per-vertex kernels that call filter_math.h / cluster_math.h directly, and
// 1, 2, 4, 8, 16 or 32 a fixed team.
int CudaEngine::team_size() const {
  if (const char* env = std::getenv("FQ_CUDA_TEAM"); env && *env && std::string(env) != "auto") {
    const long v = std::strtol(env, nullptr, 10);
    if (v == 0 || v == 1 || v == 2 || v == 4 || v == 8 || v == 16 || v == 32) return static_cast<int>(v);
  }
  const uint64_t per_sm = f_.n / uint64_t(sm_count_ > 0 ? sm_count_ : 1);
  return per_sm <= 512 ? 8 : (per_sm <= 12288 ? 4 : 1);
}

// Base quadrics by per-vertex gather (default) or by float4 atomics per triangle
// (FQ_CUDA_BASE=atomic). Measured on the H100: see docs/BENCHMARKS.md.
bool CudaEngine::gather_base_quadrics() {
  const char* env = std::getenv("FQ_CUDA_BASE");
  return !(env && std::string(env) == "atomic");
}

// Gaussian weights of the team kernels through __expf (FQ_CUDA_FAST_EXP=1) or the
// accurate exp of gaussian.h (default).
bool CudaEngine::fast_exp_enabled() {
  const char* env = std::getenv("FQ_CUDA_FAST_EXP");
  return env && std::string(env) == "1";
}

void CudaEngine::enqueue_passes(const Params& params) {
  const cudaStream_t s = stream_.get();
  const FilterParams& fp = params.f;
  const int team = team_size();
  const bool fast_exp = fast_exp_enabled();
  cuda::sort_into_grid(f_, f_.grid.layout, s);
  events_.mark("grid", s);
  const bool refine = params.filter && fp.method == FilterMethod::kQuadricRefined;
  if (gather_base_quadrics() || refine)  // the refinement needs the gather's vertex -> triangle table
    cuda::base_quadrics_gather(f_, s);
  else
    cuda::base_quadrics(f_, s);
  events_.mark("base_quadrics", s);
  if (params.cluster || fp.uses_quadrics()) {
    if (team)
      cuda::team_neighbourhood_quadrics(f_, fp.effective_sigma_b(), team, fast_exp, s);
    else
      cuda::neighbourhood_quadrics(f_, fp.effective_sigma_b(), s);
    events_.mark("neighbourhood_quadrics", s);
    if (team)
      cuda::team_diffuse_quadrics(f_, fp, team, fast_exp, s);
    else
      cuda::diffuse_quadrics(f_, fp, s);
    events_.mark("diffusion", s);
  }
  if (params.filter) {
    if (fp.uses_quadrics())
      cuda::update_positions(f_, fp, s);
    else
      cuda::bilateral_filter(f_, fp, s);
    events_.mark(fp.uses_quadrics() ? "update" : "bilateral_filter", s);
  }
  if (refine) {
    cuda::refine_positions(f_, refine_, fp.refine, s);
    events_.mark("refine", s);
  }
  if (params.cluster) {
    if (team)
      cuda::team_cluster_scores(f_, params.c, team, fast_exp, s);
    else
      cuda::cluster_scores(f_, params.c, s);
    events_.mark("score", s);
    if (team)
      cuda::team_cluster_links(f_, params.c, team, fast_exp, s);
    else
      cuda::cluster_links(f_, params.c, s);
    events_.mark("link", s);
    cuda::cluster_labels(f_, s);
    events_.mark("modes", s);
  }
  if (params.filter) {
    cuda::gather_moved(f_, s);
    events_.mark("output", s);
  }
}

void CudaEngine::run_frame(const MeshView& mesh, const Params& params, const Normalization& norm,
                           FrameResult& out) {
  const Clock::time_point t0 = Clock::now();
  FQ_CUDA_CHECK(cudaSetDevice(device_.id));
  f_.grid.layout = stage_input(mesh, norm, params.f.sigma_s);
  const double prepare_ms = ms_since(t0);
  const cudaStream_t s = stream_.get();
  const uint32_t n = f_.n, m = f_.m;

  events_.begin(s);
  FQ_CUDA_CHECK(cudaMemcpyAsync(f_.in_points.reserve(n), f_.h_points.data(), n * sizeof(Point4),
                                cudaMemcpyHostToDevice, s));
  FQ_CUDA_CHECK(cudaMemcpyAsync(f_.in_tris.reserve(3 * size_t(m)), f_.h_tris.data(),
                                3 * size_t(m) * sizeof(uint32_t), cudaMemcpyHostToDevice, s));
  events_.mark("upload", s);
  enqueue_passes(params);
  if (params.filter) {
    FQ_CUDA_CHECK(cudaMemcpyAsync(f_.h_moved.reserve(n), f_.moved_in_order.data(), n * sizeof(Vec3),
                                  cudaMemcpyDeviceToHost, s));
  }
  if (params.cluster) {
    FQ_CUDA_CHECK(cudaMemcpyAsync(f_.h_labels.reserve(n + 1), f_.labels.data(), (n + 1) * sizeof(uint32_t),
                                  cudaMemcpyDeviceToHost, s));
  }
  events_.mark("download", s);
  stream_.sync();

  const Clock::time_point t1 = Clock::now();
  finish_output(mesh, params, norm, out);
  out.timings.push_back({"normalize", normalize_ms_});  // host: checks, centre, mean edge
  out.timings.push_back({"prepare", prepare_ms});       // host: normalized points into pinned staging
  events_.collect([&](const char* name, double ms) { out.timings.push_back({name, ms}); });
  out.timings.push_back({"finish", ms_since(t1)});
}

void CudaEngine::finish_output(const MeshView& mesh, const Params& params, const Normalization& norm,
                               FrameResult& out) {
  const uint32_t n = f_.n;
  out.positions.resize(3 * size_t(n));
  if (params.filter) {
    cuda::unstage_positions(f_.h_moved.data(), n, norm, out.positions.data());
  } else {
    std::copy(mesh.positions, mesh.positions + 3 * size_t(n), out.positions.begin());
  }
  if (params.cluster) {
    out.labels.assign(f_.h_labels.data(), f_.h_labels.data() + n);
    out.num_clusters = f_.h_labels.data()[n];
  }
}

}  // namespace

namespace cuda {

void note_device_allocation() { g_allocations.fetch_add(1, std::memory_order_relaxed); }

unsigned block_size() {
  static const unsigned size = [] {
    const char* env = std::getenv("FQ_CUDA_BLOCK");
    const long v = env ? std::strtol(env, nullptr, 10) : 0;
    return v >= 32 && v <= 1024 && v % 32 == 0 ? static_cast<unsigned>(v) : 256u;
  }();
  return size;
}

unsigned blocks_for(uint64_t n) {
  if (g_fail_next_launch.exchange(false)) return 0;
  const uint64_t b = (n + block_size() - 1) / block_size();
  return b > 0 ? static_cast<unsigned>(b) : 1u;
}

void fail_next_launch() { g_fail_next_launch.store(true); }

}  // namespace cuda

uint64_t cuda_allocation_count() { return g_allocations.load(std::memory_order_relaxed); }

void cuda_fail_next_launch_for_testing() { cuda::fail_next_launch(); }

std::unique_ptr<Engine> make_cuda_engine(int device, Status* why) {
  auto unavailable = [&](std::string msg) -> std::unique_ptr<Engine> {
    (void)cudaGetLastError();
    if (why) *why = {StatusCode::kUnavailable, std::move(msg)};
    return nullptr;
  };
  int count = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&count); e != cudaSuccess)
    return unavailable(std::string("no usable CUDA device: ") + cudaGetErrorName(e) + " (" +
                       cudaGetErrorString(e) + ")");
  if (count == 0) return unavailable("no CUDA device is present");
  if (device < 0 || device >= count)
    return unavailable("CUDA device " + std::to_string(device) + " does not exist (" + std::to_string(count) +
                       " present)");
  try {
    auto engine = std::make_unique<CudaEngine>(device);
    if (why) *why = {};
    return engine;
  } catch (const cuda::CudaError& e) {
    return unavailable("could not start the CUDA engine on device " + std::to_string(device) + ": " +
                       e.what());
  }
}

}  // namespace fq
