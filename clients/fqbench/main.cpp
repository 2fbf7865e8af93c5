// fqbench: loads the shared meshes, warms the engine up, and reports per pass and in total
// the median and spread (p10/p90) of device time over repeated frames for the paper's
// rows of Tables 2 and 3, with the paper's figure, the speed-up, host<->device transfers
// (pinned) and the CPU engine's time on the same row. Prints a markdown table.
// With --codec MESH it times the frame codec against plain Draco instead (codec_bench.h), with
// --codec-device MESH the device decode against the host reader (codec_device_bench.h, CUDA
// builds), with --track-ids FRAMES the host step of temporal track A (track_bench.h).
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "clients/common/defaulted_option.h"
#include "clients/common/tool_app.h"
#include "clients/fqbench/bench_rows.h"
#include "clients/fqbench/bench_stats.h"
#include "clients/fqbench/codec_bench.h"
#include "clients/fqbench/codec_device_bench.h"
#include "clients/fqbench/neighbour_stats.h"
#include "clients/fqbench/track_bench.h"
#include "common/tool_main.h"
#include "io/mesh_io.h"
#include "kernels/cpu_engine.h"
#include "kernels/engine.h"
#include "kernels/fq_features.h"

namespace {

using namespace fq;
using namespace fq::bench;
using fq::client::add_defaulted;
using fq::client::add_ranged;

struct Options {
  std::string mesh_dir;
  std::string rows = "all";
  std::string engine = "cuda";
  int repeat = 20;
  int warmup = 3;
  int cpu_repeat = 3;
  int cpu_threads = 0;
  bool cancel_token = false;
  CudaTuning cuda;
  bool neighbour_stats = false;
  bool stats_only = false;
};

struct RowResult {
  BenchRow row;
  uint32_t vertices = 0, triangles = 0;
  PassSamples gpu;
  Spread wall, cpu;
  uint32_t clusters = 0, cpu_clusters = 0;
};

std::string default_mesh_dir() {
  const char* env = std::getenv("FQ_MESH_DIR");
  return env && *env ? env : "../shared/meshes";
}

std::string fmt(const Spread& s) {
  char b[96];
  std::snprintf(b, sizeof b, "%.3f (%.3f–%.3f)", s.median, s.p10, s.p90);
  return b;
}

std::string params_text(const Params& p) {
  char b[128];
  if (p.cluster)
    std::snprintf(b, sizeof b, "σs %.3g σr %.3g σd %.3g σq %.3g θ %.3g", p.filtering.sigma_s,
                  p.filtering.sigma_r, p.clustering.sigma_d, p.clustering.sigma_q, p.clustering.theta);
  else
    std::snprintf(b, sizeof b, "σs %.3g σr %.3g", p.filtering.sigma_s, p.filtering.sigma_r);
  return b;
}

// Runs `frames` frames; returns false (with a message) when the engine reports an error.
bool run_frames(Engine& e, const Mesh& mesh, const Params& params, int frames, PassSamples* passes,
                std::vector<double>* wall, FrameResult& r) {
  for (int k = 0; k < frames; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const Status s = e.process(mesh.view(), params, r);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!s.ok()) {
      std::fprintf(stderr, "fqbench: %s failed: %s\n", e.name().c_str(), s.message().c_str());
      return false;
    }
    if (passes) passes->add(r);
    if (wall) wall->push_back(ms);
  }
  return true;
}

bool bench_row(const Options& o, Engine& engine, CpuEngine* cpu, const Mesh& mesh, RowResult& out) {
  FrameResult r;
  std::vector<double> wall;
  if (!run_frames(engine, mesh, out.row.params, o.warmup, nullptr, nullptr, r)) return false;
  if (!run_frames(engine, mesh, out.row.params, o.repeat, &out.gpu, &wall, r)) return false;
  out.wall = spread_of(wall);
  out.clusters = r.num_clusters;
  if (cpu && o.cpu_repeat > 0) {
    PassSamples cpu_passes;
    if (!run_frames(*cpu, mesh, out.row.params, o.cpu_repeat, &cpu_passes, nullptr, r)) return false;
    out.cpu = cpu_passes.spread("frame");
    out.cpu_clusters = r.num_clusters;
  }
  return true;
}

void print_summary(const std::vector<RowResult>& results, const std::string& engine, const CudaTuning& cuda,
                   int cpu_threads) {
  std::string tuning;
  if (engine.rfind("cuda:", 0) == 0)
    tuning = " (team " +
             (cuda.team == CudaTuning::kTeamBySize ? std::string("by size") : std::to_string(cuda.team)) +
             (cuda.fast_exp ? ", __expf weights)" : ")");
  std::printf(
      "\nEngine: %s%s; device time = sum of the passes' CUDA-event times (transfers and host work "
      "excluded); ms, median (p10–p90).\n\n",
      engine.c_str(), tuning.c_str());
  std::printf(
      "| row | mesh | V | F | params | paper row | paper ms | ours: device ms | speed-up | upload ms | "
      "download ms | frame wall ms | CPU engine ms (%d thr) | clusters ours / CPU |\n",
      cpu_threads);
  std::printf("|---|---|---:|---:|---|---|---:|---|---:|---|---|---|---|---|\n");
  for (const RowResult& r : results) {
    const Spread dev = r.gpu.spread("device");
    char speed[32] = "—", paper[32] = "—", cpu[48] = "—", clusters[48] = "—";
    if (r.row.paper_ms > 0) {
      std::snprintf(paper, sizeof paper, "%.0f", r.row.paper_ms);
      std::snprintf(speed, sizeof speed, "%.0f×", r.row.paper_ms / dev.median);
    }
    if (r.cpu.count > 0) std::snprintf(cpu, sizeof cpu, "%.1f (n=%d)", r.cpu.median, r.cpu.count);
    if (r.row.params.cluster) std::snprintf(clusters, sizeof clusters, "%u / %u", r.clusters, r.cpu_clusters);
    std::printf("| %s | %s | %u | %u | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.row.id.c_str(),
                r.row.file.c_str(), r.vertices, r.triangles, params_text(r.row.params).c_str(),
                r.row.paper_row.c_str(), paper, fmt(dev).c_str(), speed, fmt(r.gpu.spread("upload")).c_str(),
                fmt(r.gpu.spread("download")).c_str(), fmt(r.wall).c_str(), cpu, clusters);
  }
}

void print_passes(const std::vector<RowResult>& results) {
  std::printf("\nPer pass, ms, median (p10–p90):\n\n");
  for (const RowResult& r : results) {
    std::printf("- %s:", r.row.id.c_str());
    for (const std::string& name : r.gpu.names()) {
      if (name == "frame") continue;
      std::printf(" %s %s;", name.c_str(), fmt(r.gpu.spread(name)).c_str());
    }
    const double device = r.gpu.spread("device").median;
    std::printf(" frame wall %s = %.2f× device\n", fmt(r.wall).c_str(),
                device > 0 ? r.wall.median / device : 0.0);
  }
}

int run(int argc, char** argv) {
  Options o;
  o.mesh_dir = default_mesh_dir();
  fq::client::ToolApp app{"fqbench: device time per pass for the paper's Table 2 and 3 rows", "fqbench"};
  app.add_option("--mesh-dir", o.mesh_dir,
                 "folder of the shared meshes (default: $FQ_MESH_DIR or ../shared/meshes)");
  add_defaulted(app, "--rows", o.rows, "comma-separated row ids, or all");
  add_defaulted(app, "--engine", o.engine, "engine to time: cuda | cpu | auto")
      ->check(CLI::IsMember({"cuda", "cpu", "auto"}));
  add_ranged(app, "--repeat", o.repeat, "timed frames per row (>= 1)", 1, 100000);
  add_ranged(app, "--warmup", o.warmup, "untimed frames first", 0, 1000);
  add_ranged(app, "--cpu-repeat", o.cpu_repeat, "CPU engine frames per row for comparison (0 = none)", 0,
             1000);
  add_defaulted(app, "--cpu-threads", o.cpu_threads, "CPU engine threads (0 = all)");
  app.add_flag("--cancel-token", o.cancel_token,
               "run frames under a cancel token that never fires, as fqd does (its cost: the CUDA engine "
               "then waits for the passes one by one)");
  add_defaulted(app, "--cuda-team", o.cuda.team,
                "CUDA lanes per vertex in the neighbourhood passes: -1 by mesh size (default), 0 one "
                "thread per vertex through the math headers, or 1, 2, 4, 8, 16, 32")
      ->check(CLI::IsMember({-1, 0, 1, 2, 4, 8, 16, 32}));
  app.add_flag("--cuda-fast-exp", o.cuda.fast_exp, "CUDA Gaussian weights through __expf (last bits differ)");
  app.add_flag("--neighbour-stats", o.neighbour_stats,
               "also print mean neighbours per vertex at each pass's radius (CPU; for FLOP floors)");
  app.add_flag("--stats-only", o.stats_only, "print only the neighbour statistics (no engine runs)");
  bool list = false;
  app.add_flag("--list", list, "list the rows and exit");
  CodecBenchOptions codec;
  auto* codec_opt =
      app.add_option("--codec", codec.mesh,
                     "codec mode: time the frame codec on MESH (a file, or a name in the mesh "
                     "folder) against plain Draco on the same chunks, instead of the engine rows");
  add_ranged(app, "--chunks", codec.chunks, "codec mode: chunks per frame", 1u, 256u);
  add_ranged(app, "--threads", codec.threads, "codec mode: codec threads", 1, 256);
  add_ranged(app, "--speed", codec.speed, "codec mode: Draco encoding = decoding speed", 0, 10);
  add_ranged(app, "--bits", codec.position_bits, "codec mode: position quantization bits", 1, 30);
  app.add_flag("--json", codec.json, "codec mode: print one JSON object instead of a table");
  CodecDeviceBenchOptions device_codec;
  auto* device_codec_opt =
      app.add_option("--codec-device", device_codec.mesh,
                     "device codec mode: time the device decode of MESH's sequential chunks against the "
                     "host reader on the same chunks (CUDA builds), instead of the engine rows");
  app.add_option("--chunk-counts", device_codec.chunks,
                 "device codec mode: one row per chunk count (default: fqpub's for the mesh, 1, 16, 64, 256)")
      ->check(CLI::Range(1u, 256u));
  add_ranged(app, "--host-threads", device_codec.host_threads, "device codec mode: the host reader's threads",
             1, 256);
  TrackBenchOptions track;
  auto* track_opt =
      app.add_option("--track-ids", track.frames_dir,
                     "track mode: time temporal track A's host step over the frames of FRAMES (a "
                     "folder, or a name in the mesh folder: crane) instead of the engine rows");
  add_ranged(app, "--frames", track.frames, "track mode: the first frames in name order", 2, 100000);
  add_ranged(app, "--noise", track.noise, "track mode: noise per frame, mean edges", 0.0, 10.0);
  app.add_option("--track-threads", track.threads,
                 "track mode: one row per thread count (default: 1 and all)")
      ->check(CLI::Range(1, 1024));
  CLI11_PARSE(app, argc, argv);

  if (*track_opt) {
    track.mesh_dir = o.mesh_dir;
    track.repeat = o.repeat;
    return run_track_bench(track);
  }
  if (*device_codec_opt) {
    device_codec.mesh_dir = o.mesh_dir;
    device_codec.repeat = o.repeat;
#if FQ_WITH_CUDA
    return run_codec_device_bench(device_codec);
#else
    std::fprintf(stderr, "fqbench: --codec-device needs the CUDA build\n");
    return 3;
#endif
  }
  if (*codec_opt) {
    codec.mesh_dir = o.mesh_dir;
    codec.repeat = o.repeat;
    return run_codec_bench(codec);
  }

  if (list) {
    for (const BenchRow& r : paper_rows())
      std::printf("%-20s %-18s %-34s paper %6.0f ms  %s\n", r.id.c_str(), r.file.c_str(), r.paper_row.c_str(),
                  r.paper_ms, params_text(r.params).c_str());
    return 0;
  }
  std::string unknown;
  const std::vector<BenchRow> rows = select_rows(o.rows, unknown);
  if (!unknown.empty()) {
    std::fprintf(stderr, "fqbench: unknown row(s): %s (see --list)\n", unknown.c_str());
    return 2;
  }
  EngineKind kind{};
  parse_engine_kind(o.engine, kind);
  StatusOr<std::unique_ptr<Engine>> made = make_engine({kind, o.cpu_threads, 0, o.cuda});
  if (!made.ok()) {
    std::fprintf(stderr, "fqbench: engine %s unavailable: %s\n", o.engine.c_str(),
                 made.status().message().c_str());
    return 3;
  }
  std::unique_ptr<Engine> engine = std::move(made).value();
  const std::atomic<bool> never{false};
  const CancelToken token(&never);
  if (o.cancel_token) engine->set_cancel_token(&token);
  std::unique_ptr<CpuEngine> cpu;
  if (o.cpu_repeat > 0) cpu = std::make_unique<CpuEngine>(o.cpu_threads);

  std::map<std::string, Mesh> meshes;
  std::vector<RowResult> results;
  for (const BenchRow& row : rows) {
    if (!meshes.count(row.file)) {
      Mesh m;
      const Status s = io::read_mesh(o.mesh_dir + "/" + row.file, m);
      if (!s.ok()) {
        std::fprintf(stderr, "fqbench: skipping %s: %s\n", row.id.c_str(), s.message().c_str());
        continue;
      }
      meshes.emplace(row.file, std::move(m));
    }
    const Mesh& mesh = meshes.at(row.file);
    RowResult res{row, mesh.num_vertices(), mesh.num_triangles(), {}, {}, {}, 0, 0};
    std::fprintf(stderr, "fqbench: %s (%u vertices)...\n", row.id.c_str(), mesh.num_vertices());
    if (!o.stats_only && !bench_row(o, *engine, cpu.get(), mesh, res)) return 1;
    results.push_back(std::move(res));
  }
  if (results.empty()) {
    std::fprintf(stderr, "fqbench: no row could be run (mesh folder %s)\n", o.mesh_dir.c_str());
    return 1;
  }
  if (!o.stats_only) {
    print_summary(results, engine->name(), o.cuda, cpu ? cpu->threads() : 0);
    print_passes(results);
  }
  if (o.neighbour_stats || o.stats_only) {
    std::printf(
        "\nMean neighbours per vertex (radius 2σ; grid cell σs):\n\n| row | V | Q' (2σb) | diffusion (2σs) | "
        "score/link (2σd) |\n|---|---:|---:|---:|---:|\n");
    for (const RowResult& r : results) {
      const NeighbourStats s = neighbour_stats(meshes.at(r.row.file).view(), r.row.params);
      std::printf("| %s | %u | %.1f | %.1f | %.1f |\n", r.row.id.c_str(), r.vertices, s.nbhd, s.diffusion,
                  s.cluster);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqbench", run, argc, argv); }
