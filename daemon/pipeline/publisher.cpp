#include "daemon/pipeline/publisher.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "wire/header_codec.h"

namespace fq::daemon {
namespace {

// Longest send -> publish believed: anything longer is a clock, not a latency.
constexpr double kMaxSendToPublishMs = 3'600'000;

// Sends that fail are logged, at most 5 a second.
LogLimiter& send_errors() {
  static LogLimiter log;
  return log;
}

wire::TemporalTrack temporal_track_to_wire(fq::TemporalTrack t) {
  switch (t) {
    case fq::TemporalTrack::kIds:
      return wire::TEMPORAL_IDS;
    case fq::TemporalTrack::kSpace:
      return wire::TEMPORAL_SPACE;
    case fq::TemporalTrack::kNone:
      break;
  }
  return wire::TEMPORAL_NONE;
}

}  // namespace

wire::ResultHeader make_result_header(const FrameJob& f, int64_t publish_ns) {
  wire::ResultHeader h;
  h.set_version(wire::kWireVersion);
  h.set_stream_id(f.stream_id);
  h.set_sequence(f.header.sequence());
  h.set_capture_time_ns(f.header.capture_time_ns());
  h.set_send_time_ns(f.header.send_time_ns());
  h.set_receive_time_ns(f.receive_ns);
  h.set_publish_time_ns(publish_ns);
  h.set_latency_ms(ms_between(f.receive_ns, publish_ns));
  for (const PassTiming& t : f.timings) {
    wire::StageTiming* st = h.add_timings();
    st->set_name(t.name);
    st->set_ms(t.ms);
  }
  // The producer's send -> publish, on two hosts' clocks when the producer is remote.
  if (f.header.send_time_ns() > 0) {
    wire::StageTiming* st = h.add_timings();
    st->set_name("send_to_publish");
    st->set_ms(ms_between(f.header.send_time_ns(), publish_ns));
  }
  h.set_engine(f.engine);
  if (!f.error.ok()) {
    h.set_status(wire::ERROR);
    h.set_error(f.error.message());
    return h;
  }
  h.set_status(h.latency_ms() > f.settings.budget_ms ? wire::LATE : wire::OK);
  h.set_cluster_count(f.result.num_clusters);
  h.set_distinct_clusters(f.distinct_clusters);
  h.set_theta(f.result.theta);
  h.set_noise_estimate(f.result.noise_estimate);
  h.set_filter_noise(f.result.filter_noise);
  h.set_temporal_track(temporal_track_to_wire(f.result.temporal_track));
  h.set_chunk_count(static_cast<uint32_t>(f.out_chunks.size()));
  h.set_vertex_count(f.mesh.num_vertices());
  h.set_form(to_wire(f.settings.output.form));
  if (f.settings.params.cluster && !f.result.labels.empty())
    h.mutable_labels()->Assign(f.result.labels.begin(), f.result.labels.end());
  return h;
}

void Publisher::run() {
  for (;;) {
    // Wakes once a second without results to read the subscriptions that came in.
    bool idle = false;
    auto item = p_.publish_queue.pop_for(std::chrono::seconds(1), idle);
    const CpuScope cpu(p_.stage_cpu[CpuStage::kPublish]);
    socket_.drain_subscriptions();
    if (item)
      accept(std::move(*item));
    else if (!idle)
      break;  // closed and drained
  }
  // Everything ticketed has arrived by now; anything still held would be a bug upstream.
  for (Stream* s : holding_) {
    std::map<uint64_t, FramePtr> held = std::move(s->order.held);  // frees s with the last frame
    for (auto& [t, f] : held) publish(*f);
  }
  socket_.close();
}

void Publisher::accept(FramePtr f) {
  if (!f->ticketed) return publish(*f);
  Stream& s = *f->stream;
  PublishOrder& o = s.order;
  if (f->ticket != o.next) {
    o.held.emplace(f->ticket, std::move(f));
    holding_.insert(&s);
    return;
  }
  publish(*f);  // f keeps the stream alive while its held frames go
  ++o.next;
  for (auto it = o.held.begin(); it != o.held.end() && it->first == o.next; it = o.held.erase(it), ++o.next)
    publish(*it->second);
  if (o.held.empty()) holding_.erase(&s);
}

void Publisher::publish(FrameJob& f) {
  const wire::ResultHeader h = make_result_header(f, wall_ns());
  const std::string header = h.SerializeAsString();
  std::vector<zmq::const_buffer> parts;
  parts.push_back(zmq::buffer(f.stream_id));
  parts.push_back(zmq::buffer(header));
  for (const std::string& c : f.out_chunks) parts.push_back(zmq::buffer(c));
  // Counted before sending, so that a consumer who got the result sees it in the counters.
  account(f, h);
  if (f.stream) p_.latest.offer(*f.stream, h, f.out_chunks, f.mesh.triangles);
  try {
    if (!socket_.send(parts) && f.stream) f.stream->count(&StreamCounters::subscriber_overflows);
  } catch (const zmq::error_t& e) {
    send_errors().log(spdlog::level::err, "publish of stream '{}' frame {} failed: {}", f.stream_id,
                      h.sequence(), e.what());
  }
  p_.recycle(f);
}

void Publisher::account(const FrameJob& f, const wire::ResultHeader& h) {
  if (!f.stream) return;  // refused before it had a stream: counted with the refusals
  Stream& s = *f.stream;
  if (h.status() == wire::ERROR) {
    if (!f.preempted) s.count(&StreamCounters::errors);  // a preempted frame is counted as such
    return;
  }
  s.count(&StreamCounters::frames_out);
  if (h.status() == wire::LATE) s.count(&StreamCounters::late);
  for (const PassTiming& t : f.timings) s.record(t.name, t.ms);
  s.record("receive_to_publish", h.latency_ms());
  if (h.send_time_ns() > 0) {
    // The producer's clock: a time in the future or far in the past (a wrong clock, or a forged
    // one) would drive the histograms' sums negative or off the scale; it is counted instead.
    const double ms = ms_between(h.send_time_ns(), h.publish_time_ns());
    if (ms >= 0 && ms <= kMaxSendToPublishMs)
      s.record("send_to_publish", ms);
    else
      s.count(&StreamCounters::bad_send_time);
  }
}

}  // namespace fq::daemon
