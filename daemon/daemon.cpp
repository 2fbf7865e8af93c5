#include "daemon/daemon.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "common/non_copyable.h"
#include "daemon/control/control_server.h"
#include "daemon/control/service_metrics.h"
#include "daemon/control/settings_audit.h"
#include "daemon/pipeline/daemon_threads.h"
#include "daemon/pipeline/ingest.h"
#include "daemon/pipeline/publisher.h"
#include "daemon/pipeline/result_socket.h"
#include "daemon/pipeline/sub_ingest.h"
#include "daemon/service/config_reload.h"

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

StatusOr<std::vector<std::unique_ptr<Engine>>> make_engines(const EngineConfig& c) {
  std::vector<std::unique_ptr<Engine>> out;
  if (c.kind == EngineKind::kCopy) {  // as many as CPU engines would be: a free engine per worker
    for (int i = 0; i < c.cpu_engines; ++i) out.push_back(make_engine({EngineKind::kCopy, 0, 0, {}}).value());
    return out;
  }
  if (c.kind != EngineKind::kCpu) {
    for (int gpu : c.gpus) {
      StatusOr<std::unique_ptr<Engine>> e = make_engine({EngineKind::kCuda, c.cpu_threads, gpu, {}});
      if (e.ok())
        out.push_back(std::move(e).value());
      else if (c.kind == EngineKind::kCuda)
        return Status{StatusCode::kUnavailable, "GPU " + std::to_string(gpu) + ": " + e.status().message()};
      else
        spdlog::info("engine auto: no CUDA engine on GPU {} ({})", gpu, e.status().message());
    }
  }
  if (out.empty() || c.cpu_alongside_gpus) {
    // The CPU engine is always there: make_engine cannot fail for it.
    for (int i = 0; i < c.cpu_engines; ++i)
      out.push_back(make_engine({EngineKind::kCpu, c.cpu_threads, 0, {}}).value());
  }
  return out;
}

Daemon::Daemon(DaemonConfig config)
    : config_(std::move(config)),
      registry_(config_),
      caps_(config_.caps),
      pipeline_(config_, registry_, caps_),
      input_context_(1),
      output_context_(1) {
  config_.resolve_auto_threads();
  tag_zmq_threads(input_context_);
  tag_zmq_threads(output_context_);
  // An engine that outruns the encoders waits instead of queueing results: frames then wait
  // in their streams' slots, where newer ones supersede them, and latency stays bounded.
  pipeline_.encode_queue.set_capacity(static_cast<size_t>(config_.encode_threads));
  pipeline_.decode_queue.set_bounds(config_.caps.max_queued_frames, config_.caps.max_queued_bytes);
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
    in.refusals.emplace_back(refusal_name(static_cast<Refusal>(r)),
                             registry_.refusals().get(static_cast<Refusal>(r)));
  for (const std::string& id : registry_.own_series_ids(wall_ns(), caps_.get()->metric_series_idle_s)) {
    StreamSettings s;
    if (registry_.find(id, s)) in.budgets_ms.emplace_back(id, s.budget_ms);
  }
  for (size_t i = 0; i < engines_.size() && i < pipeline_.engine_busy.size(); ++i)
    in.engines.push_back(
        {engines_[i]->name(), pipeline_.engine_busy.seconds(i), pipeline_.engine_busy.frames(i)});
  in.queues = {{"decode", pipeline_.decode_queue.frames()},
               {"slots", pipeline_.slots.waiting()},
               {"encode", pipeline_.encode_queue.size()},
               {"publish", pipeline_.publish_queue.size()}};
  for (size_t k = 0; k < static_cast<size_t>(MemoryKind::kCount); ++k)
    in.memory.emplace_back(memory_kind_name(static_cast<MemoryKind>(k)),
                           registry_.memory().bytes(static_cast<MemoryKind>(k)));
  in.memory_peak = registry_.memory().peak();
  in.memory_budget = registry_.memory().budget();
  in.ingest_reconnects = sub_reconnects_.load(std::memory_order_relaxed);
  in.process = read_process_stats();
  return service_metrics_text(in) + stage_cpu_metrics_text(pipeline_.stage_cpu, daemon_threads_cpu_seconds());
}

struct Daemon::Sockets {
  zmq::socket_t ingest, publish, publish_monitor, control;
  std::unique_ptr<SubProducers> sub;  ///< stays empty without [ingest] connect
  CurveServerKeys keys;               ///< with [security]
};

// Every door of fqd under the same rules: a size bound at the socket (a larger part drops the
// connection before it is buffered) and, with [security], CURVE with the ZAP allow-list.
Status Daemon::make_sockets(Sockets& s) {
  s.ingest = zmq::socket_t(input_context_, zmq::socket_type::pull);
  s.control = zmq::socket_t(input_context_, zmq::socket_type::rep);
  s.publish = zmq::socket_t(output_context_, zmq::socket_type::xpub);
  ResultSocket::configure(s.publish, static_cast<int>(config_.caps.max_subscriber_results),
                          config_.caps.max_stream_id_bytes);
  s.publish_monitor = SubscriptionGate::monitor(output_context_, s.publish);
  s.ingest.set(zmq::sockopt::linger, 0);
  // max_frame_bytes bounds the whole message, so it bounds every part too.
  s.ingest.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(config_.caps.max_frame_bytes));
  // When the decode queue is full the ingest thread stops reading: this mark (messages per
  // producer connection) is what libzmq then holds before the producer is held back.
  s.ingest.set(zmq::sockopt::rcvhwm, kIngestMark);
  // Wakes the ingest thread once a second when nothing arrives, for idle-stream expiry.
  s.ingest.set(zmq::sockopt::rcvtimeo, 1000);
  s.control.set(zmq::sockopt::linger, 0);
  s.control.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(kMaxControlBytes));
  s.publish.set(zmq::sockopt::linger, kPublishLingerMs);
  if (config_.security.enabled()) {
    FQ_RETURN_IF_ERROR(load_curve_server_keys(config_.security, s.keys));
    client_keys_ = std::make_unique<ClientKeys>(s.keys.clients);
    pipeline_.keys = client_keys_.get();
    if (!config_.security.control_keys_file.empty())
      control_keys_ = std::make_unique<ClientKeys>(s.keys.control);
    input_zap_ = std::make_unique<ZapHandler>(input_context_, *client_keys_, registry_.refusals(),
                                              control_keys_.get());
    output_zap_ = std::make_unique<ZapHandler>(output_context_, *client_keys_, registry_.refusals());
    for (zmq::socket_t* socket : {&s.ingest, &s.publish}) make_curve_server(*socket, s.keys.server);
    make_curve_server(s.control, s.keys.server, control_keys_ ? kControlZapDomain : kZapDomain);
    spdlog::info("fqd: CURVE on every socket, {} client key(s) allowed{}", s.keys.clients.size(),
                 control_keys_
                     ? fmt::format(", {} on the control socket (its own list)", s.keys.control.size())
                     : std::string());
  } else {
    for (const std::string& e :
         {config_.endpoints.ingest, config_.endpoints.publish, config_.endpoints.control})
      if (!is_local_endpoint(e))
        spdlog::warn(
            "fqd: {} is reachable from other hosts without CURVE: anyone who can connect may send "
            "frames, read results and change parameters (set [security] curve_key_file)",
            e);
  }
  if (config_.sub_ingest.connect.empty()) return {};
  return make_sub_producers(input_context_, config_.sub_ingest, config_.caps.max_frame_bytes,
                            config_.security.enabled() ? &s.keys.server : nullptr, sub_reconnects_, s.sub);
}

Status Daemon::bind_sockets(Sockets& s) {
  FQ_RETURN_IF_ERROR(bind_one(s.ingest, config_.endpoints.ingest, "ingest", endpoints_.ingest));
  FQ_RETURN_IF_ERROR(bind_one(s.publish, config_.endpoints.publish, "publish", endpoints_.publish));
  return bind_one(s.control, config_.endpoints.control, "control", endpoints_.control);
}

Status Daemon::start() {
  if (running_) return {};
  FQ_ASSIGN_OR_RETURN(engines_, make_engines(config_.engine));
  Sockets sockets;
  FQ_RETURN_IF_ERROR(make_sockets(sockets));
  FQ_RETURN_IF_ERROR(bind_sockets(sockets));
  std::vector<const Engine*> engine_list;
  for (const auto& e : engines_) engine_list.push_back(e.get());
  pipeline_.engine_busy.reset(engine_list);
  if (!config_.http.listen.empty()) {
    http_ =
        std::make_unique<HttpServer>(config_, caps_, registry_, pipeline_.latest, engine_names(), healthy_);
    http_->set_extra_metrics([this] { return service_metrics(); });
    FQ_RETURN_IF_ERROR(http_->start());
    endpoints_.http = http_->url();
  }
  // Sockets were made on this thread and are handed over whole to their owner threads.
  const SubscriptionCaps subscription_caps{config_.caps.max_subscriptions,
                                           config_.caps.max_subscription_bytes};
  publisher_thread_ = std::thread([this, s = std::move(sockets.publish),
                                   m = std::move(sockets.publish_monitor), subscription_caps]() mutable {
    name_this_thread("publish");
    Publisher(
        ResultSocket(std::move(s), std::move(m), subscription_caps, registry_.refusals(), client_keys_.get()),
        pipeline_)
        .run();
  });
  for (int i = 0; i < config_.encode_threads; ++i)
    encoders_.emplace_back([this] {
      name_this_thread("encode");
      run_encode_worker(pipeline_);
    });
  pipeline_.slots.set_engines(static_cast<int>(engines_.size()));
  for (auto& e : engines_)
    workers_.emplace_back([this, eng = e.get()] {
      name_this_thread("engine");
      run_engine_worker(pipeline_, *eng);
    });
  pipeline_.decode_queue.set_decoders(config_.decode_threads);
  for (int i = 0; i < config_.decode_threads; ++i)
    decoders_.emplace_back([this] {
      name_this_thread("decode");
      run_decode_worker(pipeline_);
    });
  control_thread_ = std::thread([this, s = std::move(sockets.control)]() mutable {
    name_this_thread("control");
    run_control(std::move(s), registry_, caps_, control_keys_ ? control_keys_.get() : client_keys_.get());
  });
  const auto& ids = config_.sub_ingest.streams;
  ingest_ = std::make_unique<Ingest>(std::move(sockets.ingest), pipeline_, std::move(sockets.sub),
                                     std::set<std::string>(ids.begin(), ids.end()));
  ingest_->start();
  running_ = true;
  healthy_ = true;
  if (config_.stats.interval_s > 0)
    stats_log_ = std::make_unique<StatsLog>(registry_, config_.stats.interval_s);
  std::string names;
  for (const std::string& n : engine_names()) names += (names.empty() ? "" : ", ") + n;
  spdlog::info("fqd: engines [{}], {} decode / {} encode threads", names, config_.decode_threads,
               config_.encode_threads);
  spdlog::info("fqd: ingest {} (PULL), publish {} (XPUB), control {} (REP)", endpoints_.ingest,
               endpoints_.publish, endpoints_.control);
  if (http_) spdlog::info("fqd: http {} (/metrics /healthz /streams, viewer at /)", endpoints_.http);
  for (const std::string& ep : config_.sub_ingest.connect)
    spdlog::info("fqd: ingest also from {} (SUB), streams [{}]", ep,
                 config_.sub_ingest.streams.empty()
                     ? std::string("all")
                     : fmt::format("{}", fmt::join(config_.sub_ingest.streams, ", ")));
  return {};
}

Status Daemon::reload(const DaemonConfig& fresh) {
  const std::vector<std::string> restart = restart_only_changes(config_, fresh);
  if (!restart.empty())
    return invalid_argument(fmt::format(
        "{} changed, which takes effect only at a restart (nothing was applied)", fmt::join(restart, ", ")));
  // Everything that can fail is read first, so that a bad file changes nothing.
  CurveServerKeys keys;
  if (fresh.security.enabled()) FQ_RETURN_IF_ERROR(load_curve_server_keys(fresh.security, keys));
  HttpAccessRules access;
  if (http_) FQ_RETURN_IF_ERROR(load_http_access(fresh.http, fresh.security.enabled(), access));
  std::map<std::string, StreamSettings> before;
  for (const std::string& id : registry_.list()) registry_.find(id, before[id]);
  registry_.reload(fresh.defaults, fresh.streams);
  for (const std::string& id : registry_.list()) {
    StreamSettings after;
    if (!registry_.find(id, after)) continue;
    auto it = before.find(id);
    log_settings_changes(id, it == before.end() ? fresh.defaults : it->second, after, "reload");
  }
  caps_.set(fresh.caps);
  pipeline_.decode_queue.set_bounds(fresh.caps.max_queued_frames, fresh.caps.max_queued_bytes);
  registry_.memory().set_budget(fresh.caps.memory_budget_mb << 20);  // what is kept sheds at the next charge
  if (client_keys_) client_keys_->set(std::move(keys.clients));      // revoked keys' connections are cut
  if (control_keys_) control_keys_->set(std::move(keys.control));
  if (http_) http_->set_access(std::move(access));
  spdlog::set_level(spdlog::level::from_str(fresh.log_level));
  return {};
}

void Daemon::stop() {
  if (!running_) return;
  running_ = false;
  healthy_ = false;
  if (http_) http_->stop();
  if (stats_log_) stats_log_->stop();
  // Blocking receives on the input sockets return ETERM; their threads close them.
  input_context_.shutdown();
  if (ingest_) ingest_->join();
  if (control_thread_.joinable()) control_thread_.join();
  input_context_.close();
  if (input_zap_) input_zap_->join();
  // Drain stage by stage: each queue closes once everything before it has finished. Frames
  // already received may finish within the grace; then the engines stop theirs and every
  // frame left gets an error result (so a huge frame does not hold the exit for minutes).
  {
    const Alarm grace(std::chrono::duration<double>(caps_.get()->stop_grace_s), pipeline_.cancel_engines);
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
