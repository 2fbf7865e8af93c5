// fqd's per-stream cluster id tracking: each stream that clusters with track_ids on keeps
// its previous frame's vertices and ids (kernels/label_tracking.h), so that a region keeps
// its id, and its colour, from frame to frame. Thread-safe; streams do not wait on each other.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "daemon/frame_job.h"
#include "kernels/label_tracking.h"

namespace fq::daemon {

class LabelTracks {
 public:
  /// For a clustered frame of a stream with track_ids on: replaces the labels by the
  /// stream's stable ids and result.num_clusters by their bound (f.distinct_clusters keeps
  /// the count). Otherwise forgets the stream's previous frame, so tracking restarts cleanly.
  /// kCancelled when `token` expired first: the frame keeps the engine's numbering and the
  /// stream's next frame is matched with the last one tracked.
  Status apply(FrameJob& f, int threads, const CancelToken& token);

 private:
  struct Track {
    std::mutex mutex;
    LabelTracker tracker;
  };
  Track& track_of(const std::string& stream_id);

  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Track>> tracks_;
};

}  // namespace fq::daemon
