// fqd's stable cluster ids: a stream of captures of one object (shuffled vertices, fresh
// noise) keeps its cluster ids when track_ids is on; target_clusters and the result's
// distinct_clusters / theta.
#include <gtest/gtest.h>

#include "eval/capture_sequence.h"
#include "eval/label_persistence.h"
#include "kernels/frame_prep.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

client::FrameSpec spec_for(const std::string& stream) {
  client::FrameSpec s;
  s.stream_id = stream;
  return s;
}

double persistence(const client::ReceivedResult& a, const client::ReceivedResult& b, float cell) {
  return label_persistence(a.mesh.positions.data(), a.labels.data(), a.mesh.num_vertices(),
                           b.mesh.positions.data(), b.labels.data(), b.mesh.num_vertices(), cell);
}

daemon::DaemonConfig tracking_config() {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.filter = false;
  c.defaults.params.cluster = true;
  c.defaults.params.clustering.sigma_d = 3.f;
  c.defaults.params.clustering.target_clusters = 6;
  return c;
}

TEST(DaemonLabelTracking, IdsPersistAcrossCapturesAndTheSwitchTurnsItOff) {
  DaemonHarness h(tracking_config());
  const Mesh clean = make_cube(10);
  const float cell = float(mean_edge_length(clean.view()));
  std::vector<client::ReceivedResult> got;
  for (uint64_t i = 0; i < 3; ++i) {
    h.send(capture_frame(clean, 0.0, 0.05, 40 + i), spec_for("cam"), i);
    got.push_back(h.receive_decoded("cam"));
    const wire::ResultHeader& hd = got.back().header;
    EXPECT_EQ(hd.distinct_clusters(), 6u) << "the target count";
    EXPECT_GE(hd.cluster_count(), hd.distinct_clusters()) << "cluster_count bounds the ids";
    EXPECT_GT(hd.theta(), 0.f);
    EXPECT_LE(hd.theta(), 1.f);
  }
  EXPECT_GE(persistence(got[0], got[1], cell), 0.9);
  EXPECT_GE(persistence(got[1], got[2], cell), 0.9);

  // Off: each frame is numbered by the engine alone. Over several shuffled captures the
  // engine's numbering (by root vertex index) changes, which tracking would have hidden.
  wire::ControlRequest set;
  set.mutable_set_params()->set_stream_id("cam");
  set.mutable_set_params()->mutable_params()->set_track_ids(false);
  ASSERT_TRUE(h.control(set).ok());
  wire::ControlRequest get;
  get.mutable_get_params()->set_stream_id("cam");
  EXPECT_FALSE(h.control(get).params().track_ids());
  double worst = 1.0;
  client::ReceivedResult prev = std::move(got.back());
  for (uint64_t i = 3; i < 8; ++i) {
    h.send(capture_frame(clean, 0.0, 0.05, 40 + i), spec_for("cam"), i);
    client::ReceivedResult r = h.receive_decoded("cam");
    EXPECT_EQ(r.header.cluster_count(), r.header.distinct_clusters()) << "untracked ids are 0..K-1";
    worst = std::min(worst, persistence(prev, r, cell));
    prev = std::move(r);
  }
  EXPECT_LT(worst, 0.9) << "untracked numbering never changed: the test shows nothing";
}

}  // namespace
}  // namespace fq::test
