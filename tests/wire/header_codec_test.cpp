// Strict parsing of the wire headers (version first) and the ParamOverrides mapping.
#include "wire/header_codec.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "tests/support/param_values.h"

namespace fq::wire {
namespace {

using google::protobuf::util::MessageDifferencer;

FrameHeader full_header() {
  FrameHeader h;
  h.set_version(kWireVersion);
  h.set_stream_id("scanner-7");
  h.set_sequence(123456789012ull);
  h.set_capture_time_ns(-5);
  h.set_send_time_ns(1700000000123456789ll);
  h.mutable_params()->set_sigma_s(3.5f);
  h.mutable_params()->set_mode(BF);
  h.mutable_params()->set_constrained(false);  // set to its default: must still travel
  h.set_compute(FILTER_AND_CLUSTER);
  h.set_chunk_count(4);
  h.set_vertex_count(34834);
  return h;
}

/// A varint field `number` = `value` in raw wire format (tag then value).
std::string raw_varint_field(uint32_t number, uint64_t value) {
  std::string out;
  for (uint64_t v : {uint64_t(number) << 3, value}) {
    while (v >= 0x80) {
      out += char(0x80 | (v & 0x7f));
      v >>= 7;
    }
    out += char(v);
  }
  return out;
}

TEST(HeaderCodec, FrameHeaderRoundTrip) {
  const FrameHeader in = full_header();
  FrameHeader out;
  ASSERT_TRUE(parse_frame_header(in.SerializeAsString(), out).ok());
  EXPECT_TRUE(MessageDifferencer::Equals(in, out));
  EXPECT_TRUE(out.params().has_sigma_s());
  EXPECT_TRUE(out.params().has_constrained());
  EXPECT_FALSE(out.params().has_sigma_r());
}

TEST(HeaderCodec, ResultHeaderRoundTrip) {
  ResultHeader in;
  in.set_version(kWireVersion);
  in.set_stream_id("s");
  in.set_status(LATE);
  auto* t = in.add_timings();
  t->set_name("filter");
  t->set_ms(12.5);
  in.set_form(MESH);
  in.set_vertex_count(3);
  for (uint32_t l : {0u, 7u, 300u}) in.add_labels(l);
  ResultHeader out;
  ASSERT_TRUE(parse_result_header(in.SerializeAsString(), out).ok());
  EXPECT_TRUE(MessageDifferencer::Equals(in, out));
}

TEST(HeaderCodec, ResultLabelsAreOnePerVertex) {
  ResultHeader in;
  in.set_version(kWireVersion);
  in.set_stream_id("s");
  in.set_vertex_count(4);
  in.add_labels(1);
  ResultHeader out;
  const Status s = parse_result_header(in.SerializeAsString(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("1 labels for 4 vertices"), std::string::npos) << s.message();
}

TEST(HeaderCodec, AVersionOneResultIsRefusedNamingBothVersions) {
  // A result header as version 1 wrote it: version 1, status LATE and its `bool late = 13`,
  // which version 2 no longer has. The version, not the unknown field, is what is reported.
  const std::string v1 = raw_varint_field(1, 1) +
                         std::string(
                             "\x12\x03"
                             "cam",
                             5) +
                         raw_varint_field(8, 1) + raw_varint_field(13, 1);
  ResultHeader out;
  const Status s = parse_result_header(v1, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("result header: wire version 1 not supported (this build speaks version 2)"),
            std::string::npos)
      << s.message();
}

TEST(HeaderCodec, UnknownTopLevelFieldRejected) {
  const std::string bytes = full_header().SerializeAsString() + raw_varint_field(99, 1);
  FrameHeader out;
  const Status s = parse_frame_header(bytes, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("unknown field number 99"), std::string::npos) << s.message();
}

TEST(HeaderCodec, UnknownNestedFieldRejected) {
  ParamOverrides p;
  p.set_sigma_s(1.f);
  const std::string params = p.SerializeAsString() + raw_varint_field(42, 7);
  FrameHeader h = full_header();
  h.clear_params();
  std::string bytes = h.SerializeAsString();
  bytes += char((6 << 3) | 2);  // field 6 (params), length-delimited
  bytes += char(params.size());
  bytes += params;
  FrameHeader out;
  const Status s = parse_frame_header(bytes, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("params."), std::string::npos) << s.message();
}

TEST(HeaderCodec, UnknownEnumValueRejected) {
  FrameHeader h = full_header();
  h.clear_compute();
  FrameHeader out;
  const Status s = parse_frame_header(h.SerializeAsString() + raw_varint_field(7, 9), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("Compute"), std::string::npos) << s.message();
}

TEST(HeaderCodec, WrongVersionRejected) {
  static_assert(kWireVersion == 2);
  for (uint32_t v : {0u, 1u, 3u}) {
    FrameHeader h = full_header();
    h.set_version(v);
    FrameHeader out;
    const Status s = parse_frame_header(h.SerializeAsString(), out);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
    EXPECT_NE(s.message().find("wire version " + std::to_string(v) +
                               " not supported (this build speaks version 2)"),
              std::string::npos)
        << s.message();
  }
}

TEST(HeaderCodec, FrameRulesEnforced) {
  FrameHeader out;
  FrameHeader h = full_header();
  h.clear_stream_id();
  EXPECT_EQ(parse_frame_header(h.SerializeAsString(), out).code(), StatusCode::kInvalidInput);
  for (uint32_t chunks : {0u, kMaxChunks + 1}) {
    h = full_header();
    h.set_chunk_count(chunks);
    EXPECT_EQ(parse_frame_header(h.SerializeAsString(), out).code(), StatusCode::kInvalidInput) << chunks;
  }
  h.set_chunk_count(kMaxChunks);
  EXPECT_TRUE(parse_frame_header(h.SerializeAsString(), out).ok());
}

TEST(HeaderCodec, GarbageRejected) {
  FrameHeader out;
  EXPECT_EQ(parse_frame_header(std::string("\xff\xff\xff\xff\xff", 5), out).code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(parse_frame_header("", out).code(), StatusCode::kInvalidInput);  // version 0
  EXPECT_EQ(parse_frame_header("hello, fqd", out).code(), StatusCode::kInvalidInput);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::string bytes(1 + rng() % 64, '\0');
    for (char& c : bytes) c = char(rng());
    EXPECT_FALSE(parse_frame_header(bytes, out).ok()) << "trial " << trial;
  }
}

TEST(HeaderCodec, ControlRequestNeedsARequest) {
  ControlRequest r;
  r.set_version(kWireVersion);
  ControlRequest out;
  EXPECT_EQ(parse_control_request(r.SerializeAsString(), out).code(), StatusCode::kInvalidInput);
  r.mutable_set_params()->set_stream_id("a");
  r.mutable_set_params()->set_compute(CLUSTER);
  ASSERT_TRUE(parse_control_request(r.SerializeAsString(), out).ok());
  EXPECT_TRUE(out.set_params().has_compute());
  r.clear_version();  // version 0: a request without a version is refused too
  EXPECT_NE(parse_control_request(r.SerializeAsString(), out).message().find("wire version 0"),
            std::string::npos);
}

TEST(HeaderCodec, OverridesApplyOnlySetFields) {
  ParamOverrides o;
  o.set_sigma_s(4.f);
  o.set_mode(BF);
  o.set_theta(0.5f);
  o.set_cluster_method(EUCLIDEAN);
  Params p;
  const Params defaults;
  ASSERT_TRUE(apply_overrides(o, p).ok());
  EXPECT_EQ(p.filtering.sigma_s, 4.f);
  EXPECT_EQ(p.filtering.method, FilterMethod::kBilateral);
  EXPECT_EQ(p.clustering.theta, 0.5f);
  EXPECT_EQ(p.clustering.method, ClusterMethod::kEuclidean);
  EXPECT_EQ(p.filtering.sigma_r, defaults.filtering.sigma_r);
  EXPECT_EQ(p.filtering.tikhonov, defaults.filtering.tikhonov);
  EXPECT_EQ(p.clustering.sigma_d, defaults.clustering.sigma_d);
  EXPECT_TRUE(validate(p).ok());
  ParamOverrides keep;
  keep.set_mode(MODE_DEFAULT);
  ASSERT_TRUE(apply_overrides(keep, p).ok());
  EXPECT_EQ(p.filtering.method, FilterMethod::kBilateral);
}

TEST(HeaderCodec, OverridesAreValidatedAfterwards) {
  Params p;
  ParamOverrides o;
  o.set_sigma_s(-1.f);
  ASSERT_TRUE(apply_overrides(o, p).ok());
  EXPECT_FALSE(validate(p).ok());
  o.set_sigma_s(NAN);
  ASSERT_TRUE(apply_overrides(o, p).ok());
  EXPECT_FALSE(validate(p).ok());
  ParamOverrides theta;
  theta.set_theta(1.5f);
  Params q;
  q.cluster = true;  // theta is only checked when clustering
  ASSERT_TRUE(apply_overrides(theta, q).ok());
  EXPECT_FALSE(validate(q).ok());
}

TEST(HeaderCodec, BadEnumOverrideLeavesParamsUntouched) {
  ParamOverrides o;
  o.set_sigma_s(9.f);
  o.set_mode(static_cast<FilterMode>(7));
  Params p;
  EXPECT_EQ(apply_overrides(o, p).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(p.filtering.sigma_s, Params{}.filtering.sigma_s);
  EXPECT_EQ(apply_compute(static_cast<Compute>(5), p).code(), StatusCode::kInvalidArgument);
  ParamOverrides g;
  g.set_target_clusters(12);
  g.set_cluster_geometry(static_cast<ClusterGeometryWire>(9));
  EXPECT_EQ(apply_overrides(g, p).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(p.clustering.target_clusters, 0u);
}

TEST(HeaderCodec, ComputeMapping) {
  Params p;
  ASSERT_TRUE(apply_compute(CLUSTER, p).ok());
  EXPECT_TRUE(!p.filter && p.cluster);
  EXPECT_EQ(compute_of(p), CLUSTER);
  ASSERT_TRUE(apply_compute(COMPUTE_DEFAULT, p).ok());
  EXPECT_EQ(compute_of(p), CLUSTER);
  ASSERT_TRUE(apply_compute(FILTER_AND_CLUSTER, p).ok());
  EXPECT_EQ(compute_of(p), FILTER_AND_CLUSTER);
  ASSERT_TRUE(apply_compute(FILTER, p).ok());
  EXPECT_TRUE(p.filter && !p.cluster);
}

TEST(HeaderCodec, EveryFilterMethodRoundTrips) {
  for (FilterMethod m : {FilterMethod::kQuadric, FilterMethod::kBilateral, FilterMethod::kQuadricRefined}) {
    Params p;
    p.filtering.method = m;
    ParamOverrides w;
    params_to_wire(p, w);
    Params back;
    back.filtering.method = m == FilterMethod::kQuadric ? FilterMethod::kBilateral : FilterMethod::kQuadric;
    ASSERT_TRUE(apply_overrides(w, back).ok());
    EXPECT_EQ(back.filtering.method, m) << test::mode_name(m);
  }
}

TEST(HeaderCodec, ParamsRoundTrip) {
  Params p;
  p.filter = false;
  p.cluster = true;
  p.filtering = {FilterMethod::kBilateral, 3.f, 0.5f, 1.25f, 0.75f, true, 0.f, {}};
  p.clustering = {ClusterMethod::kEuclidean, 7.f, 2.f, 0.8f};
  p.clustering.target_clusters = 42;
  p.clustering.geometry = ClusterGeometry::kFiltered;
  p.clustering.min_cluster_size = 9;
  p.clustering.track_ids = false;
  p.clustering.sticky_rings = 5;
  ParamOverrides w;
  params_to_wire(p, w);
  ParamOverrides via_bytes;
  ASSERT_TRUE(parse_strict(w.SerializeAsString(), via_bytes, "params").ok());
  Params back;  // defaults everywhere: every field must come from the wire
  ASSERT_TRUE(apply_overrides(via_bytes, back).ok());
  ASSERT_TRUE(apply_compute(compute_of(p), back).ok());
  EXPECT_EQ(back.filter, p.filter);
  EXPECT_EQ(back.cluster, p.cluster);
  EXPECT_EQ(back.filtering.method, p.filtering.method);
  EXPECT_EQ(back.filtering.sigma_s, p.filtering.sigma_s);
  EXPECT_EQ(back.filtering.sigma_r, p.filtering.sigma_r);
  EXPECT_EQ(back.filtering.sigma_b, p.filtering.sigma_b);
  EXPECT_EQ(back.filtering.sigma_n, p.filtering.sigma_n);
  EXPECT_EQ(back.filtering.constrained, p.filtering.constrained);
  EXPECT_EQ(back.filtering.tikhonov, p.filtering.tikhonov);
  EXPECT_EQ(back.clustering.method, p.clustering.method);
  EXPECT_EQ(back.clustering.sigma_d, p.clustering.sigma_d);
  EXPECT_EQ(back.clustering.sigma_q, p.clustering.sigma_q);
  EXPECT_EQ(back.clustering.theta, p.clustering.theta);
  EXPECT_EQ(back.clustering.target_clusters, p.clustering.target_clusters);
  EXPECT_EQ(back.clustering.geometry, p.clustering.geometry);
  EXPECT_EQ(back.clustering.min_cluster_size, p.clustering.min_cluster_size);
  EXPECT_EQ(back.clustering.track_ids, p.clustering.track_ids);
  EXPECT_EQ(back.clustering.sticky_rings, p.clustering.sticky_rings);
  EXPECT_EQ(w.ByteSizeLong(), via_bytes.ByteSizeLong());
  const auto* d = ParamOverrides::descriptor();
  for (int i = 0; i < d->field_count(); ++i)
    EXPECT_TRUE(via_bytes.GetReflection()->HasField(via_bytes, d->field(i))) << d->field(i)->name();
}

}  // namespace
}  // namespace fq::wire
