// Each frame is read and given its noise before the clock starts; each round starts a new track
// (its first frame restarts the track from the raw frame, the second builds what the
// connectivity alone decides), so the medians are those of a stream in its steady state.
#include "clients/fqbench/track_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "clients/fqbench/bench_stats.h"
#include "core/parallel_for.h"
#include "eval/noise.h"
#include "io/mesh_io.h"
#include "kernels/frame_prep.h"
#include "kernels/temporal.h"
#include "kernels/temporal_ids.h"

namespace fq::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Frame {
  Mesh mesh;
  double mean_edge = 0.0;
};

bool load(const TrackBenchOptions& o, std::vector<Frame>& frames) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::is_directory(o.frames_dir) ? fs::path(o.frames_dir) : fs::path(o.mesh_dir) / o.frames_dir;
  std::vector<fs::path> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  if (ec || files.empty()) {
    std::fprintf(stderr, "fqbench: no frames in %s\n", dir.c_str());
    return false;
  }
  std::sort(files.begin(), files.end());
  files.resize(std::min(files.size(), size_t(o.frames)));
  for (size_t i = 0; i < files.size(); ++i) {
    Frame f;
    if (const Status s = io::read_mesh(files[i].string(), f.mesh); !s.ok()) {
      std::fprintf(stderr, "fqbench: %s: %s\n", files[i].c_str(), s.message().c_str());
      return false;
    }
    add_gaussian_noise(f.mesh, o.noise, uint64_t(o.seed) + i);
    f.mean_edge = mean_edge_length(f.mesh.view(), 0);
    frames.push_back(std::move(f));
  }
  return true;
}

struct Row {
  int threads = 0;
  std::vector<double> fingerprint, connectivity, average, keep, total;
  int ran = 0, refused = 0, mismatches = 0;
  double bytes_per_vertex = 0.0;            ///< what the track keeps at the end of a round
  uint64_t digest = 0xcbf29ce484222325ULL;  // FNV-1a over one round's averaged inputs
};

void add_to_digest(const std::vector<float>& v, uint64_t& h) {
  const auto* b = reinterpret_cast<const unsigned char*>(v.data());
  for (size_t i = 0; i < v.size() * sizeof(float); ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
}

// One round over the sequence on a new track; the engine's scale is the last frame's mean edge.
void one_round(const TrackBenchOptions& o, const std::vector<Frame>& frames, bool timed, Row& row) {
  TemporalHistory history;
  TemporalScratch scratch;
  std::vector<float> averaged;
  for (size_t i = 0; i < frames.size(); ++i) {
    const MeshView mesh = frames[i].mesh.view();
    const double edge = i > 0 ? frames[i - 1].mean_edge : frames[i].mean_edge;
    const Clock::time_point t0 = Clock::now();
    const uint64_t hashed = connectivity_fingerprint(mesh, row.threads);
    const double t_fingerprint = ms_since(t0);
    // What the engine runs: the track's kept triangles compared, the hash when they differ.
    const Clock::time_point tc = Clock::now();
    const uint64_t fingerprint = frame_connectivity(mesh, history.ids, row.threads);
    const double t_connectivity = ms_since(tc);
    if (fingerprint != hashed) {
      std::fprintf(stderr, "fqbench: frame %zu: frame_connectivity is not the frame's fingerprint\n", i);
      row.mismatches++;
    }
    const Clock::time_point t1 = Clock::now();
    const IdStep step =
        average_with_ids(mesh, fingerprint, edge, o.strength, history.ids, averaged, scratch, row.threads);
    const double t_average = ms_since(t1);
    double t_keep = 0.0;
    if (step.ran) {  // the run's result stands in for the averaged input: the same work
      const Clock::time_point t2 = Clock::now();
      keep_averaged_result(mesh, averaged, edge, history);
      t_keep = ms_since(t2);
    }
    row.bytes_per_vertex = double(history.ids.bytes()) / mesh.num_vertices;
    if (!timed) {  // the warm-up round gives the digest
      if (step.ran) add_to_digest(averaged, row.digest);
      continue;
    }
    if (i == 0) continue;
    row.fingerprint.push_back(t_fingerprint);
    row.connectivity.push_back(t_connectivity);
    row.average.push_back(t_average);
    row.keep.push_back(t_keep);
    row.total.push_back(t_connectivity + t_average + t_keep);
    row.ran += step.ran ? 1 : 0;
    row.refused += step.refused ? 1 : 0;
  }
}

std::string fmt(const std::vector<double>& v) {
  const Spread s = spread_of(v);
  char b[64];
  std::snprintf(b, sizeof b, "%.3f (%.3f)", s.median, s.p90);
  return b;
}

}  // namespace

int run_track_bench(const TrackBenchOptions& o) {
  std::vector<Frame> frames;
  if (!load(o, frames)) return 1;
  if (frames.size() < 2) {
    std::fprintf(stderr, "fqbench: track A needs two frames or more\n");
    return 1;
  }
  std::vector<int> threads = o.threads;
  if (threads.empty()) {
    threads = {1};
    if (hardware_threads() > 1) threads.push_back(hardware_threads());
  }
  std::printf(
      "\n%s: %zu frames (%u V, %u F), noise %g, strength %g; ms per frame from the second, median "
      "(p90) of %d rounds\n\n",
      o.frames_dir.c_str(), frames.size(), frames[0].mesh.num_vertices(), frames[0].mesh.num_triangles(),
      o.noise, double(o.strength), o.repeat);
  std::printf(
      "| threads | fingerprint (hashed) | connectivity (engine's) | average_with_ids | "
      "keep_averaged_result | track A step | ran / refused | track bytes / vertex | digest |\n"
      "|---:|---:|---:|---:|---:|---:|---|---:|---|\n");
  bool mismatched = false;
  for (int t : threads) {
    Row row;
    row.threads = t;
    one_round(o, frames, false, row);  // warm-up: buffers and the thread pool
    for (int r = 0; r < o.repeat; ++r) one_round(o, frames, true, row);
    std::printf("| %d | %s | %s | %s | %s | %s | %d / %d | %.1f | %016llx |\n", t,
                fmt(row.fingerprint).c_str(), fmt(row.connectivity).c_str(), fmt(row.average).c_str(),
                fmt(row.keep).c_str(), fmt(row.total).c_str(), row.ran / o.repeat, row.refused / o.repeat,
                row.bytes_per_vertex, static_cast<unsigned long long>(row.digest));
    mismatched = mismatched || row.mismatches > 0;
  }
  return mismatched ? 1 : 0;
}

}  // namespace fq::bench
