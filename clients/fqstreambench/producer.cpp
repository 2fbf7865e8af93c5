#include "clients/fqstreambench/producer.h"

#include <chrono>
#include <thread>

#include "common/thread_cpu.h"
#include "eval/noise.h"

namespace fq::bench {

Status Producer::prepare(const Mesh& mesh, const ProducerOptions& o) {
  options_ = o;
  frames_.clear();
  const int n = o.noise > 0 ? std::max(1, o.variants) : 1;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) {
    const Mesh m = frame_mesh(mesh, i);
    std::vector<std::string> parts;
    FQ_RETURN_IF_ERROR(client::build_frame(m.view(), o.spec, 0, parts));
    frames_.push_back(std::move(parts));
  }
  encode_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  return {};
}

Mesh Producer::frame_mesh(const Mesh& mesh, int i) const {
  Mesh m = mesh;
  if (options_.noise > 0) add_gaussian_noise(m, options_.noise, options_.seed + static_cast<uint64_t>(i));
  return m;
}

Producer::Sent Producer::run(zmq::context_t& ctx, const std::string& endpoint, const std::atomic<bool>& stop,
                             int64_t measure_from_ns) {
  zmq::socket_t push(ctx, zmq::socket_type::push);
  push.set(zmq::sockopt::linger, 2000);
  push.connect(endpoint);
  using clock = std::chrono::steady_clock;
  const int64_t cpu0 = thread_cpu_ns();
  const auto period = std::chrono::duration<double>(1.0 / options_.fps);
  const auto start = clock::now() + std::chrono::duration_cast<clock::duration>(period * options_.phase);
  Sent sent;
  for (uint64_t i = 0; !stop; ++i) {
    const auto due = start + std::chrono::duration_cast<clock::duration>(period * static_cast<double>(i));
    if (std::chrono::duration<double>(due - start).count() >= options_.seconds) break;
    std::this_thread::sleep_until(due);  // pacing the frame rate
    std::vector<std::string>& parts = frames_[i % frames_.size()];
    const int64_t now = client::restamp_frame(parts, i);
    client::send_parts(push, parts);
    ++sent.all;
    if (now >= measure_from_ns) ++sent.measured;
  }
  push.close();
  sent.cpu_ms = static_cast<double>(thread_cpu_ns() - cpu0) * 1e-6;
  return sent;
}

}  // namespace fq::bench
