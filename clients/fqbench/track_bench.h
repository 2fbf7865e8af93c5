// fqbench --track-ids: the host cost of temporal track A (kernels/temporal_ids.h) alone, the
// step Engine::run_own takes in front of either engine's run on a stream that keeps its
// connectivity, over a folder of capture frames with fresh noise each frame.
#pragma once

#include <string>
#include <vector>

namespace fq::bench {

struct TrackBenchOptions {
  std::string frames_dir;  ///< a folder of frames, or a name in mesh_dir (e.g. crane)
  std::string mesh_dir;
  int frames = 60;     ///< the first frames in name order
  double noise = 0.2;  ///< mean edges, seeded seed + frame index (as fqfilter --sequence)
  int seed = 1;
  float strength = 0.75f;    ///< the stream's temporal strength
  int repeat = 20;           ///< rounds over the sequence; medians over every frame of every round
  std::vector<int> threads;  ///< one table row each (empty: 1 and every hardware thread)
};

/// Runs the step over the sequence for each thread count and prints a Markdown table: median
/// and p90 ms per frame of the fingerprint, the averaging and the history it leaves, and a
/// digest of the averaged inputs (equal for every thread count). Returns the exit code.
int run_track_bench(const TrackBenchOptions& o);

}  // namespace fq::bench
