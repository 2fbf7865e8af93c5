// Track A's step on the device (kernels/cuda/id_pass.cuh) against the host's average_with_ids:
// the same averaged input bit for bit, frame after frame, the same decisions (ran, refused,
// restarts), with the stream's state moving between the two and several streams taking turns
// on one pass. Skips without a device.
#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "eval/noise.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/id_pass.cuh"
#include "kernels/cuda/stream.cuh"
#include "kernels/cuda_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/temporal.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

bool have_device() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

// Frame t of a stream that keeps its connectivity: `clean` under a travelling wave of a few
// mean edges (a motion that bends within the wide estimate's rings), shifted by `shift`, with
// fresh noise of `sigma` mean edges.
Mesh wave_frame(const Mesh& clean, double edge, int t, double sigma, uint64_t seed, float shift = 0.f) {
  Mesh m = clean;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    float* p = &m.positions[3 * size_t(v)];
    const double phase = 2.0 * M_PI * (p[0] / (12.0 * edge)) + 0.3 * t;
    p[1] += float(0.8 * edge * std::sin(phase));
    p[0] += shift + float(0.2 * edge * t);
  }
  add_gaussian_noise(m, sigma, seed);
  return m;
}

// Bitwise equality of two float arrays: the index of the first difference, or -1.
long first_difference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<uint32_t>(a[i]) != std::bit_cast<uint32_t>(b[i])) return long(i);
  return -1;
}

class CudaIdPass : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_device()) GTEST_SKIP() << "no CUDA device";
    stream_.emplace();
  }

  // One frame on the host with `host` and on the device with `device`: the same step and the
  // same averaged input, and the two tracks the same afterwards.
  void expect_same_step(const Mesh& frame, double edge, IdTrack& host, IdTrack& device,
                        bool on_device = true) {
    const uint64_t f = connectivity_fingerprint(frame.view(), 2);
    std::vector<float> out_host, out_device;
    const IdStep a = average_with_ids(frame.view(), f, edge, 0.75f, host, out_host, host_scratch_, 2);
    const IdStep b =
        on_device
            ? pass_.step(frame.view(), f, edge, 0.75f, device, out_device, device_scratch_, 2, stream_->get())
            : average_with_ids(frame.view(), f, edge, 0.75f, device, out_device, device_scratch_, 2);
    EXPECT_EQ(a.ran, b.ran);
    EXPECT_EQ(a.refused, b.refused);
    EXPECT_EQ(a.residual, b.residual) << "the same median level, bit for bit";
    EXPECT_NEAR(a.share, b.share, 1e-5f);
    EXPECT_NEAR(a.wide, b.wide, 1e-5f);
    if (a.ran) {
      EXPECT_EQ(first_difference(out_host, out_device), -1) << "the averaged input";
    }
    EXPECT_EQ(first_difference(host.averaged, device.averaged), -1) << "the track's state";
    EXPECT_EQ(host.frames, device.frames);
    EXPECT_EQ(host.connectivity, device.connectivity);
  }

  cuda::IdPass pass_;
  std::optional<cuda::Stream> stream_;  // made once a device is known to be there
  TemporalScratch host_scratch_, device_scratch_;
};

TEST_F(CudaIdPass, AveragesAsTheHostDoesFrameAfterFrame) {
  const Mesh sphere = make_icosphere(5, 10.f);  // 10242 vertices, as crane's count
  const double edge = mean_edge_length(sphere.view(), 2);
  IdTrack host, device;
  int ran = 0;
  for (int t = 0; t < 8; ++t) {
    SCOPED_TRACE("frame " + std::to_string(t));
    const Mesh frame = wave_frame(sphere, edge, t, 0.2 * edge, 100 + t);
    expect_same_step(frame, edge, host, device);
    ran += host.frames > 1 ? 1 : 0;
  }
  EXPECT_EQ(ran, 7) << "every frame after the first averaged";
}

// The step's launches are recorded once and replayed (launch_graph.cuh): each replay reads its
// own frame's values (a mean edge and an origin that change every frame), not the first's.
TEST_F(CudaIdPass, ReplaysItsRecordedLaunchesWithEachFramesValues) {
  const Mesh sphere = make_icosphere(5, 10.f);
  const double edge = mean_edge_length(sphere.view(), 2);
  IdTrack host, device;
  for (int t = 0; t < 6; ++t) {
    SCOPED_TRACE("frame " + std::to_string(t));
    const Mesh frame = wave_frame(sphere, edge, t, 0.2 * edge, 300 + t, 3.f * float(t * edge));
    expect_same_step(frame, edge * (1.0 + 0.03 * t), host, device);
  }
  EXPECT_EQ(host.frames, 6u);
  EXPECT_EQ(pass_.chains_recorded(), 1u) << "one stream of one size: recorded once";
}

// A launch that fails while the step's chain is being recorded is thrown as the CUDA error, and
// the next frame records the chain again and runs as the host's (nothing of the failed
// recording is kept, and the stream is out of capture).
TEST_F(CudaIdPass, ALaunchFailingWhileRecordedIsThrownAndTheNextFrameRuns) {
  const Mesh sphere = make_icosphere(4, 10.f);
  const double edge = mean_edge_length(sphere.view(), 2);
  IdTrack host, device;
  expect_same_step(wave_frame(sphere, edge, 0, 0.2 * edge, 40), edge, host, device);
  const Mesh failing = wave_frame(sphere, edge, 1, 0.2 * edge, 41);
  const uint64_t f = connectivity_fingerprint(failing.view(), 2);
  std::vector<float> out;
  cuda_fail_next_launch_for_testing();
  EXPECT_THROW(pass_.step(failing.view(), f, edge, 0.75f, device, out, device_scratch_, 2, stream_->get()),
               cuda::CudaError);
  EXPECT_EQ(pass_.chains_recorded(), 0u);
  EXPECT_EQ(device.frames, 1u) << "the failed frame left the track as it was";
  for (int t = 2; t < 5; ++t) {
    SCOPED_TRACE("frame " + std::to_string(t));
    expect_same_step(wave_frame(sphere, edge, t, 0.2 * edge, 40 + t), edge, host, device);
  }
  EXPECT_EQ(pass_.chains_recorded(), 1u);
  EXPECT_EQ(cudaStreamQuery(stream_->get()), cudaSuccess);
}

// Ids that do not follow the surface (positions scattered over several mean edges) are refused
// on both, and the tracks restart from the raw frame alike: the next frame, measured against that
// scattered frame, is refused too, and the one after runs again.
TEST_F(CudaIdPass, RefusesAndRestartsAsTheHostDoes) {
  const Mesh sphere = make_icosphere(4, 10.f);
  const double edge = mean_edge_length(sphere.view(), 2);
  IdTrack host, device;
  expect_same_step(wave_frame(sphere, edge, 0, 0.2 * edge, 1), edge, host, device);
  expect_same_step(wave_frame(sphere, edge, 1, 0.2 * edge, 2), edge, host, device);
  EXPECT_EQ(device.frames, 2u);
  expect_same_step(wave_frame(sphere, edge, 2, 5.0 * edge, 3), edge, host, device);
  EXPECT_EQ(device.frames, 1u) << "refused: the track restarts";
  expect_same_step(wave_frame(sphere, edge, 3, 0.2 * edge, 4), edge, host, device);
  EXPECT_EQ(device.frames, 1u) << "refused against the scattered frame";
  expect_same_step(wave_frame(sphere, edge, 4, 0.2 * edge, 5), edge, host, device);
  EXPECT_EQ(device.frames, 2u);
}

// A stream's state may be written by the host between device frames (another engine ran the
// frame): the pass reads the host's averaged input then, not its stale copy.
TEST_F(CudaIdPass, FollowsATrackTheHostWroteBetweenItsFrames) {
  const Mesh sphere = make_icosphere(4, 10.f);
  const double edge = mean_edge_length(sphere.view(), 2);
  IdTrack host, moving;
  const char* where = "DDHDHHD";
  for (int t = 0; where[t] != 0; ++t) {
    SCOPED_TRACE(std::string("frame ") + std::to_string(t) + " on " + where[t]);
    expect_same_step(wave_frame(sphere, edge, t, 0.2 * edge, 20 + t), edge, host, moving, where[t] == 'D');
  }
}

// More streams than the pass keeps copies of, each with its own connectivity and size, taking
// turns: each stream's steps are the host's.
TEST_F(CudaIdPass, StreamsTakingTurnsEachKeepTheirOwnTrack) {
  constexpr int kStreams = cuda::IdPass::kCopies + 2;
  std::vector<Mesh> shapes;
  std::vector<double> edges;
  for (int k = 0; k < kStreams; ++k) {
    shapes.push_back(k % 2 == 0 ? make_icosphere(3 + k % 3, 10.f) : make_cube(10 + k, 5.f));
    edges.push_back(mean_edge_length(shapes.back().view(), 2));
  }
  std::vector<IdTrack> host(kStreams), device(kStreams);
  for (int t = 0; t < 4; ++t)
    for (int k = 0; k < kStreams; ++k) {
      SCOPED_TRACE("stream " + std::to_string(k) + " frame " + std::to_string(t));
      expect_same_step(wave_frame(shapes[k], edges[k], t, 0.2 * edges[k], 1000 * k + t), edges[k], host[k],
                       device[k]);
    }
}

}  // namespace
}  // namespace fq::test
