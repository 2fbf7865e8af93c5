#include "daemon/pipeline/label_tracks.h"

#include "daemon/stream/stream.h"

namespace fq::daemon {

Status track_labels(FrameJob& f, int threads, const CancelToken& token) {
  FrameResult& r = f.result;
  f.distinct_clusters = r.num_clusters;
  LabelTrack& t = f.stream->track;
  std::lock_guard<std::mutex> lock(t.mutex);
  const ClusterParams& c = f.settings.params.clustering;
  if (!f.settings.params.cluster || !c.track_ids || r.labels.empty()) {
    t.tracker.reset();
    t.charge.release();
    return {};
  }
  // Frames of one stream may finish out of order on several engines: each is matched with
  // the frame tracked just before it, which is at worst a frame or two older.
  TrackingOptions o;
  o.cell = static_cast<float>(r.mean_edge);
  o.max_distance = 8.f * o.cell;
  o.threads = threads;
  o.triangles = f.mesh.triangles.data();
  o.num_triangles = f.mesh.num_triangles();
  o.sticky_rings = static_cast<int>(c.sticky_rings);
  Status s = t.tracker.track_until(token, r.positions.data(), f.mesh.num_vertices(), r.labels, r.num_clusters,
                                   o, r.num_clusters);
  Stream& stream = *f.stream;
  stream.kept_ns.store(wall_ns(), std::memory_order_relaxed);
  if (!t.charge.set(stream.memory, MemoryKind::kLabelTrack, kLabelTrackBytesPerVertex * f.mesh.num_vertices(),
                    Shed::kHistories, &stream)) {
    // Over the memory budget with nothing else left to drop: tracking restarts next frame.
    t.tracker.reset();
    t.charge.release();
    stream.count(&StreamCounters::memory_resets);
  }
  return s;
}

}  // namespace fq::daemon
