#include "clients/fqstreambench/collector.h"

#include "clients/common/frame_sender.h"
#include "clients/common/result_receiver.h"
#include "common/thread_cpu.h"

namespace fq::bench {

Status Collector::connect(zmq::context_t& ctx, const std::string& publish, const std::string& ingest) {
  sub_ = zmq::socket_t(ctx, zmq::socket_type::sub);
  sub_.set(zmq::sockopt::rcvhwm, 1000000);
  sub_.set(zmq::sockopt::subscribe, "");
  sub_.set(zmq::sockopt::rcvtimeo, 100);
  sub_.connect(publish);
  zmq::socket_t push(ctx, zmq::socket_type::push);
  push.set(zmq::sockopt::linger, 0);
  push.connect(ingest);
  // A tetrahedron-like probe: the smallest closed mesh the engines accept.
  Mesh probe;
  probe.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  probe.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  client::FrameSpec spec;
  spec.stream_id = "__probe";
  spec.compute = wire::FILTER;
  for (uint64_t attempt = 0; attempt < 300; ++attempt) {
    std::vector<std::string> parts;
    FQ_RETURN_IF_ERROR(client::build_frame(probe.view(), spec, attempt, parts));
    client::send_parts(push, parts);
    client::ReceivedResult r;
    while (!client::timed_out(client::receive_result(sub_, r)))
      if (r.topic == "__probe") return {};
  }
  return {StatusCode::kUnavailable, "no result from fqd at " + publish + " within 30 s"};
}

double Collector::run(const std::atomic<bool>& stop, int64_t measure_from_ns, bool decode) {
  const int64_t cpu0 = thread_cpu_ns();
  while (!stop) {
    client::ReceivedResult r;
    const StatusOr<bool> got = client::receive_result(sub_, r);
    if (client::timed_out(got) || r.topic == "__probe") continue;
    Status why = got.status();
    if (why.ok() && decode) why = client::decode_result(r, 1);
    if (why.ok() && decode) why = client::check_result(r);
    std::lock_guard<std::mutex> lock(mutex_);
    ++received_[r.topic];
    if (r.header.send_time_ns() < measure_from_ns) continue;
    stats_[r.topic].add(r, why.ok());
    overall_.add(r, why.ok());
  }
  sub_.close();
  return static_cast<double>(thread_cpu_ns() - cpu0) * 1e-6;
}

uint64_t Collector::received(const std::string& stream) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = received_.find(stream);
  return it == received_.end() ? 0 : it->second;
}

std::map<std::string, client::StreamStats> Collector::per_stream() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

client::StreamStats Collector::overall() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return overall_;
}

}  // namespace fq::bench
