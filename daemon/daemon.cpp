#include "daemon/daemon.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "common/non_copyable.h"
#include "daemon/control_server.h"
#include "daemon/daemon_threads.h"
#include "daemon/ingest.h"
#include "daemon/publisher.h"
#include "daemon/result_socket.h"
#include "daemon/service_metrics.h"
#include "daemon/settings_audit.h"
#include "daemon/sub_ingest.h"

namespace fq::daemon {
namespace {

// Lets the publisher flush what it has queued when the daemon stops.
constexpr int kPublishLingerMs = 2000;

// Sets `flag` after `delay` on a thread of its own unless disarmed first (destruction
// disarms and joins).
class Alarm : NonCopyable {
 public:
  Alarm(std::chrono::duration<double> delay, std::atomic<bool>& flag)
      : thread_([this, delay, &flag] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (!disarmed_cv_.wait_for(lock, delay, [&] { return disarmed_; })) flag = true;
        }) {}
  ~Alarm() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      disarmed_ = true;
    }
    disarmed_cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable disarmed_cv_;
  bool disarmed_ = false;
  std::thread thread_;  // last: starts once the members above exist
};

void join_all(std::vector<std::thread>& threads) {
  for (std::thread& t : threads)
    if (t.joinable()) t.join();
  threads.clear();
}

Status bind_one(zmq::socket_t& s, const std::string& endpoint, const char* role, std::string& bound) {
  try {
    s.bind(endpoint);
  } catch (const zmq::error_t& e) {
    return invalid_argument(std::string("cannot bind the ") + role + " endpoint " + endpoint + ": " +
                            e.what());
  }
  bound = s.get(zmq::sockopt::last_endpoint);
  return {};
}

}  // namespace

Status make_engines(const EngineConfig& c, std::vector<std::unique_ptr<Engine>>& out) {
  out.clear();
  if (c.kind == EngineKind::kCopy) {  // as many as CPU engines would be: a free engine per worker
    for (int i = 0; i < c.cpu_engines; ++i) out.push_back(make_engine({EngineKind::kCopy, 0, 0, {}}).value());
    return {};
  }
  if (c.kind != EngineKind::kCpu) {
    for (int gpu : c.gpus) {
      StatusOr<std::unique_ptr<Engine>> e = make_engine({EngineKind::kCuda, c.cpu_threads, gpu, {}});
      if (e.ok())
        out.push_back(std::move(e).value());
      else if (c.kind == EngineKind::kCuda)
        return {StatusCode::kUnavailable, "GPU " + std::to_string(gpu) + ": " + e.status().message()};
      else
        spdlog::info("engine auto: no CUDA engine on GPU {} ({})", gpu, e.status().message());
    }
  }
  if (out.empty() || c.cpu_alongside_gpus) {
    // The CPU engine is always there: make_engine cannot fail for it.
    for (int i = 0; i < c.cpu_engines; ++i)
      out.push_back(make_engine({EngineKind::kCpu, c.cpu_threads, 0, {}}).value());
  }
  return {};
}

Daemon::Daemon(DaemonConfig config)
    : config_(std::move(config)),
      registry_(config_),
      pipeline_(config_, registry_),
      input_context_(1),
      output_context_(1) {
  config_.resolve_auto_threads();
  tag_zmq_threads(input_context_);
  tag_zmq_threads(output_context_);
  // An engine that outruns the encoders waits instead of queueing results: frames then wait
  // in their streams' slots, where newer ones supersede them, and latency stays bounded.
  pipeline_.encode_queue.set_capacity(static_cast<size_t>(config_.encode_threads));
}

Daemon::~Daemon() { stop(); }

std::vector<std::string> Daemon::engine_names() const {
  std::vector<std::string> names;
  for (const auto& e : engines_) names.push_back(e->name());
  return names;
}

CpuUsage Daemon::cpu_usage() const {
  CpuUsage u;
  for (size_t s = 0; s < u.stage_seconds.size(); ++s)
    u.stage_seconds[s] = pipeline_.stage_cpu.seconds(static_cast<CpuStage>(s));
  u.threads_seconds = daemon_threads_cpu_seconds();  // after the stages: never below their sum
  return u;
}

std::string Daemon::service_metrics() const {
  ServiceMetricsInput in;
  for (size_t r = 0; r < static_cast<size_t>(Refusal::kCount); ++r)
    in.refusals.emplace_back(refusal_name(static_cast<Refusal>(r)), registry_.refusals().get(static_cast<Refusal>(r)));
  for (const std::string& id : registry_.list()) {
    StreamSettings s;
    if (registry_.find(id, s)) in.budgets_ms.emplace_back(id, s.budget_ms);
  }
  for (size_t i = 0; i < engines_.size() && i < pipeline_.engine_busy.size(); ++i)
    in.engines.push_back({engines_[i]->name(), pipeline_.engine_busy.seconds(i), pipeline_.engine_busy.frames(i)});
  in.queues = {{"decode", pipeline_.decode_queue.size()},
               {"slots", pipeline_.slots.waiting()},
               {"encode", pipeline_.encode_queue.size()},
               {"publish", pipeline_.publish_queue.size()}};
  in.process = read_process_stats();
  return service_metrics_text(in) + stage_cpu_metrics_text(pipeline_.stage_cpu, daemon_threads_cpu_seconds());
}

Status Daemon::bind_sockets(zmq::socket_t& ingest, zmq::socket_t& publish, zmq::socket_t& control) {
  ingest = zmq::socket_t(input_context_, zmq::socket_type::pull);
  control = zmq::socket_t(input_context_, zmq::socket_type::rep);
  publish = zmq::socket_t(output_context_, zmq::socket_type::xpub);
  ResultSocket::configure(publish, static_cast<int>(config_.caps.max_subscriber_results));
  ingest.set(zmq::sockopt::linger, 0);
  // Refused at the socket: a peer sending a larger part is disconnected before the part is
  // buffered (max_frame_bytes bounds the whole message, so it bounds every part too).
  ingest.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(config_.caps.max_frame_bytes));
  // Wakes the ingest thread once a second when nothing arrives, for idle-stream expiry.
  ingest.set(zmq::sockopt::rcvtimeo, 1000);
  control.set(zmq::sockopt::linger, 0);
  publish.set(zmq::sockopt::linger, kPublishLingerMs);
  if (config_.security.enabled()) {
    CurveServerKeys keys;
    FQ_RETURN_IF_ERROR(load_curve_server_keys(config_.security, keys));
    input_zap_ = std::make_unique<ZapHandler>(input_context_, keys.clients, registry_.refusals());
    output_zap_ = std::make_unique<ZapHandler>(output_context_, keys.clients, registry_.refusals());
    for (zmq::socket_t* s : {&ingest, &publish, &control}) make_curve_server(*s, keys.server);
    spdlog::info("fqd: CURVE on every socket, {} client key(s) allowed", keys.clients.size());
  } else {
    for (const std::string& e : {config_.endpoints.ingest, config_.endpoints.publish, config_.endpoints.control})
      if (!is_local_endpoint(e))
        spdlog::warn("fqd: {} is reachable from other hosts without CURVE: anyone who can connect may send "
                     "frames, read results and change parameters (set [security] curve_key_file)", e);
  }
  FQ_RETURN_IF_ERROR(bind_one(ingest, config_.endpoints.ingest, "ingest", endpoints_.ingest));
  FQ_RETURN_IF_ERROR(bind_one(publish, config_.endpoints.publish, "publish", endpoints_.publish));
  return bind_one(control, config_.endpoints.control, "control", endpoints_.control);
}

Status Daemon::start() {
  if (running_) return {};
  FQ_RETURN_IF_ERROR(make_engines(config_.engine, engines_));
  zmq::socket_t ingest, publish, control;
  FQ_RETURN_IF_ERROR(bind_sockets(ingest, publish, control));
  zmq::socket_t sub;  // stays empty without [ingest] connect
  if (!config_.sub_ingest.connect.empty()) FQ_RETURN_IF_ERROR(make_sub_socket(input_context_, config_.sub_ingest, sub));
  std::vector<const Engine*> engine_list;
  for (const auto& e : engines_) engine_list.push_back(e.get());
  pipeline_.engine_busy.reset(engine_list);
  if (!config_.http.listen.empty()) {
    http_ = std::make_unique<HttpServer>(config_, registry_, pipeline_.latest, engine_names(), healthy_);
    http_->set_extra_metrics([this] { return service_metrics(); });
    FQ_RETURN_IF_ERROR(http_->start());
    endpoints_.http = http_->url();
  }
  // Sockets were made on this thread and are handed over whole to their owner threads.
  publisher_thread_ = std::thread([this, s = std::move(publish)]() mutable {
    name_this_thread("publish");
    Publisher(std::move(s), pipeline_).run();
  });
  for (int i = 0; i < config_.encode_threads; ++i)
    encoders_.emplace_back([this] {
      name_this_thread("encode");
      run_encode_worker(pipeline_);
    });
  for (auto& e : engines_)
    workers_.emplace_back([this, eng = e.get()] {
      name_this_thread("engine");
      run_engine_worker(pipeline_, *eng);
    });
  for (int i = 0; i < config_.decode_threads; ++i)
    decoders_.emplace_back([this] {
      name_this_thread("decode");
      run_decode_worker(pipeline_);
    });
  control_thread_ = std::thread([this, s = std::move(control)]() mutable {
    name_this_thread("control");
    run_control(std::move(s), registry_);
  });
  if (sub) {
    ingest_thread_ = std::thread([this, pull = std::move(ingest), sub = std::move(sub)]() mutable {
      name_this_thread("ingest");
      const auto& ids = config_.sub_ingest.streams;
      run_sub_ingest(std::move(pull), std::move(sub), pipeline_, std::set<std::string>(ids.begin(), ids.end()));
    });
  } else {
    ingest_thread_ = std::thread([this, s = std::move(ingest)]() mutable {
      name_this_thread("ingest");
      run_ingest(std::move(s), pipeline_);
    });
  }
  running_ = true;
  healthy_ = true;
  if (config_.stats.interval_s > 0) stats_log_ = std::make_unique<StatsLog>(registry_, config_.stats.interval_s);
  std::string names;
  for (const std::string& n : engine_names()) names += (names.empty() ? "" : ", ") + n;
  spdlog::info("fqd: engines [{}], {} decode / {} encode threads", names, config_.decode_threads,
               config_.encode_threads);
  spdlog::info("fqd: ingest {} (PULL), publish {} (XPUB), control {} (REP)", endpoints_.ingest,
               endpoints_.publish, endpoints_.control);
  if (http_) spdlog::info("fqd: http {} (/metrics /healthz /streams, viewer at /)", endpoints_.http);
  for (const std::string& ep : config_.sub_ingest.connect)
    spdlog::info("fqd: ingest also from {} (SUB), streams [{}]", ep,
                 config_.sub_ingest.streams.empty() ? std::string("all") : fmt::format("{}", fmt::join(config_.sub_ingest.streams, ", ")));
  return {};
}

std::vector<std::string> Daemon::reload_streams(const DaemonConfig& fresh) {
  std::map<std::string, StreamSettings> before;
  for (const std::string& id : registry_.list()) registry_.find(id, before[id]);
  registry_.reload(fresh.defaults, fresh.streams);
  for (const std::string& id : registry_.list()) {
    StreamSettings after;
    if (!registry_.find(id, after)) continue;
    auto it = before.find(id);
    log_settings_changes(id, it == before.end() ? fresh.defaults : it->second, after, "reload");
  }
  std::vector<std::string> restart;
  const DaemonConfig& c = config_;
  const Endpoints& e = fresh.endpoints;
  if (e.ingest != c.endpoints.ingest || e.publish != c.endpoints.publish || e.control != c.endpoints.control)
    restart.push_back("endpoints");
  if (fresh.http.listen != c.http.listen || fresh.http.web_root != c.http.web_root) restart.push_back("http");
  if (fresh.engine.kind != c.engine.kind || fresh.engine.gpus != c.engine.gpus ||
      fresh.engine.cpu_engines != c.engine.cpu_engines || fresh.engine.cpu_threads != c.engine.cpu_threads ||
      fresh.engine.cpu_alongside_gpus != c.engine.cpu_alongside_gpus)
    restart.push_back("engine");
  if (fresh.caps.max_vertices != c.caps.max_vertices || fresh.caps.max_frame_bytes != c.caps.max_frame_bytes ||
      fresh.caps.max_streams != c.caps.max_streams)
    restart.push_back("caps");
  if (fresh.stats.interval_s != c.stats.interval_s) restart.push_back("stats");
  return restart;
}

void Daemon::stop() {
  if (!running_) return;
  running_ = false;
  healthy_ = false;
  if (http_) http_->stop();
  if (stats_log_) stats_log_->stop();
  // Blocking receives on the input sockets return ETERM; their threads close them.
  input_context_.shutdown();
  if (ingest_thread_.joinable()) ingest_thread_.join();
  if (control_thread_.joinable()) control_thread_.join();
  input_context_.close();
  if (input_zap_) input_zap_->join();
  // Drain stage by stage: each queue closes once everything before it has finished. Frames
  // already received may finish within the grace; then the engines stop theirs and every
  // frame left gets an error result (so a huge frame does not hold the exit for minutes).
  {
    const Alarm grace(std::chrono::duration<double>(config_.caps.stop_grace_s), pipeline_.cancel_engines);
    pipeline_.decode_queue.close();
    join_all(decoders_);
    pipeline_.slots.close();
    join_all(workers_);
  }
  pipeline_.encode_queue.close();
  join_all(encoders_);
  pipeline_.publish_queue.close();
  if (publisher_thread_.joinable()) publisher_thread_.join();
  output_context_.close();
  if (output_zap_) output_zap_->join();
  spdlog::info("fqd: stopped");
}

}  // namespace fq::daemon
