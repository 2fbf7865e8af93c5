// fqstreambench: sustains a frame rate on one or more streams for a duration and reports
// receive->publish and send->receive latency percentiles, achieved fps, drops and the
// per-stage times. Runs fqd in-process (engine from the options or a config file) or
// against a running fqd (--connect).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "clients/common/control_client.h"
#include "clients/common/defaulted_option.h"
#include "clients/common/draco_floor.h"
#include "clients/common/override_options.h"
#include "clients/common/tool_app.h"
#include "clients/fqstreambench/collector.h"
#include "clients/fqstreambench/producer.h"
#include "clients/fqstreambench/report.h"
#include "core/parallel_for.h"
#include "daemon/daemon.h"
#include "io/mesh_io.h"
#include "wire/header_codec.h"

namespace {

struct Args {
  std::string mesh, mesh_dir, config, engine = "auto", ingest, publish, control, stream_prefix = "bench";
  std::vector<int> gpus{0};
  int streams = 1, cpu_threads = 0, decode_threads = 0, encode_threads = 0;
  double warmup = 1.0, drain = 30.0, budget_ms = 0.0;
  int encode_speed = 10;
  std::string result_form;         ///< in-process fqd: "positions" | "mesh" ("" = config/default)
  std::string phases = "aligned";  ///< when in the frame period the streams send
  bool connect = false, json = false, markdown = false, decode = false;
  fq::bench::ProducerOptions producer;
  fq::client::OverrideArgs overrides;
};

struct Endpoints {
  std::string ingest, publish, control;
};

std::string resolve_mesh(const Args& a) {
  namespace fs = std::filesystem;
  if (a.mesh_dir.empty() && fs::exists(a.mesh)) return a.mesh;
  std::string dir = a.mesh_dir;
  if (dir.empty()) dir = std::getenv("FQ_MESH_DIR") ? std::getenv("FQ_MESH_DIR") : "../shared/meshes";
  return (fs::path(dir) / a.mesh).string();
}

fq::Status start_daemon(const Args& a, std::unique_ptr<fq::daemon::Daemon>& d, Endpoints& ep,
                        std::string& engine) {
  fq::daemon::DaemonConfig c;
  if (!a.config.empty()) {
    FQ_RETURN_IF_ERROR(fq::daemon::load_config(a.config, c));
  } else {
    if (!fq::parse_engine_kind(a.engine, c.engine.kind))
      return fq::invalid_argument("--engine must be auto, cuda, cpu or copy");
    c.engine.gpus = a.gpus;
    c.engine.cpu_threads = a.cpu_threads;
    c.decode_threads = a.decode_threads;
    c.encode_threads = a.encode_threads;
  }
  c.endpoints = {"tcp://127.0.0.1:*", "tcp://127.0.0.1:*", "tcp://127.0.0.1:*"};
  c.http.listen.clear();  // no HTTP listener or stats lines while measuring
  c.stats.interval_s = 0;
  if (a.budget_ms > 0) c.defaults.budget_ms = a.budget_ms;
  c.defaults.output.encode_speed = c.defaults.output.decode_speed = a.encode_speed;
  if (!a.result_form.empty() && !fq::daemon::parse_result_form(a.result_form, c.defaults.output.form))
    return fq::invalid_argument("--result-form must be positions or mesh");
  d = std::make_unique<fq::daemon::Daemon>(c);
  FQ_RETURN_IF_ERROR(d->start());
  ep = {d->endpoints().ingest, d->endpoints().publish, d->endpoints().control};
  for (const std::string& n : d->engine_names()) engine += (engine.empty() ? "" : "+") + n;
  return {};
}

// Counters of every stream from the control socket (empty on failure).
std::map<std::string, fq::wire::StreamCounters> counters(zmq::context_t& ctx, const std::string& control) {
  zmq::socket_t req(ctx, zmq::socket_type::req);
  req.set(zmq::sockopt::linger, 0);
  req.connect(control);
  fq::wire::ControlRequest q;
  q.mutable_get_counters();
  fq::wire::ControlReply r;
  std::map<std::string, fq::wire::StreamCounters> out;
  if (!fq::client::control_call(req, q, r).ok()) return out;
  for (const auto& c : r.counters()) out[c.stream_id()] = c;
  return out;
}

// The stream's settings as fqd reports them ("?" fields when it does not answer).
void stream_settings(zmq::context_t& ctx, const std::string& control, const std::string& stream,
                     fq::bench::RunInfo& run) {
  zmq::socket_t req(ctx, zmq::socket_type::req);
  req.set(zmq::sockopt::linger, 0);
  req.connect(control);
  fq::wire::ControlRequest q;
  q.mutable_get_params()->set_stream_id(stream);
  fq::wire::ControlReply r;
  run.compute = run.result_form = "?";
  if (!fq::client::control_call(req, q, r).ok()) return;
  fq::Params p;
  if (fq::wire::apply_compute(r.compute(), p).ok()) run.compute = fq::daemon::compute_name(p);
  run.result_form = fq::daemon::result_form_name(fq::daemon::from_wire(r.result_form()));
}

// True once fqd accounted for every frame sent and each published result has arrived.
bool settled(const fq::bench::RunInfo& run, const std::map<std::string, fq::wire::StreamCounters>& now,
             const fq::bench::Collector& col) {
  for (const auto& [id, sent] : run.sent) {
    auto it = now.find(id);
    if (it == now.end()) return false;
    const fq::wire::StreamCounters b = run.before.count(id) ? run.before.at(id) : fq::wire::StreamCounters{};
    const fq::wire::StreamCounters& c = it->second;
    const uint64_t in = c.frames_in() - b.frames_in();
    const uint64_t published = c.frames_out() + c.errors() - b.frames_out() - b.errors();
    const uint64_t dropped = c.superseded() + c.dropped_stale() - b.superseded() - b.dropped_stale();
    if (in != sent || in != published + dropped || col.received(id) < published) return false;
  }
  return true;
}

// Plain Draco's decode + encode CPU of one frame of the run (the floor fqd's CPU is set beside),
// on fqd's codec threads for its chunks.
void measure_floor(const Args& a, const fq::Mesh& frame, fq::bench::CpuInfo& cpu) {
  fq::wire::CodecOptions opt;
  opt.threads = std::max(1, std::min<int>(fq::hardware_threads(), static_cast<int>(a.producer.spec.chunks)));
  opt.encode_speed = opt.decode_speed = a.encode_speed;
  opt.position_bits = a.producer.spec.position_bits;
  const fq::client::FloorCpu f = fq::client::floor_cpu(frame.view(), a.producer.spec.chunks, opt, 5);
  cpu.floor_decode_ms = f.decode_ms;
  cpu.floor_encode_ms = f.encode_ms;
}

// fqd's CPU between two readings, by stage name.
void cpu_delta(const fq::daemon::CpuUsage& before, const fq::daemon::CpuUsage& after,
               fq::bench::CpuInfo& cpu) {
  cpu.measured = true;
  for (size_t s = 0; s < before.stage_seconds.size(); ++s)
    cpu.stage_seconds[fq::daemon::cpu_stage_name(static_cast<fq::daemon::CpuStage>(s))] =
        after.stage_seconds[s] - before.stage_seconds[s];
  cpu.threads_seconds = after.threads_seconds - before.threads_seconds;
}

fq::Status run_streams(const Args& a, const fq::Mesh& mesh, const Endpoints& ep,
                       const fq::daemon::Daemon* daemon, fq::bench::RunInfo& run) {
  zmq::context_t ctx(1);
  fq::bench::Collector col;
  FQ_RETURN_IF_ERROR(col.connect(ctx, ep.publish, ep.ingest));
  std::vector<fq::bench::Producer> producers(static_cast<size_t>(a.streams));
  for (int i = 0; i < a.streams; ++i) {
    fq::bench::ProducerOptions o = a.producer;
    o.spec.stream_id = a.stream_prefix + std::to_string(i);
    o.seed += static_cast<uint64_t>(i) * 1000;
    if (a.phases == "spread") o.phase = static_cast<double>(i) / a.streams;
    FQ_RETURN_IF_ERROR(producers[size_t(i)].prepare(mesh, o));
  }
  if (daemon) measure_floor(a, producers[0].frame_mesh(mesh, 0), run.cpu);
  run.before = counters(ctx, ep.control);
  const fq::daemon::CpuUsage cpu_before = daemon ? daemon->cpu_usage() : fq::daemon::CpuUsage{};
  std::atomic<bool> stop_sending{false}, stop_collecting{false};
  const int64_t measure_from = fq::client::now_ns() + static_cast<int64_t>(a.warmup * 1e9);
  std::thread collector([&] { run.cpu.collector_ms = col.run(stop_collecting, measure_from, a.decode); });
  fq::bench::HostProbe probe;
  probe.start();
  std::vector<std::thread> senders;
  std::vector<fq::bench::Producer::Sent> sent(producers.size());
  for (size_t i = 0; i < producers.size(); ++i)
    senders.emplace_back([&, i] { sent[i] = producers[i].run(ctx, ep.ingest, stop_sending, measure_from); });
  for (std::thread& t : senders) t.join();
  run.host = probe.stop();
  for (int i = 0; i < a.streams; ++i) {
    run.sent[a.stream_prefix + std::to_string(i)] = sent[size_t(i)].all;
    run.sent_measured[a.stream_prefix + std::to_string(i)] = sent[size_t(i)].measured;
    run.cpu.producers_ms += sent[size_t(i)].cpu_ms;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(a.drain);
  while (!settled(run, counters(ctx, ep.control), col) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // waiting for the tail of results
  stop_collecting = true;
  collector.join();
  run.after = counters(ctx, ep.control);
  if (daemon) cpu_delta(cpu_before, daemon->cpu_usage(), run.cpu);
  stream_settings(ctx, ep.control, a.stream_prefix + "0", run);
  if (!a.overrides.compute.empty()) run.compute = a.overrides.compute;
  run.per_stream = col.per_stream();
  run.overall = col.overall();
  return {};
}

// Every command-line option, into `a`.
void add_options(CLI::App& app, Args& a) {
  app.add_option("mesh", a.mesh, "mesh file, or a file name in --mesh-dir (e.g. bunny.ply)")->required();
  app.add_option("--mesh-dir", a.mesh_dir, "folder of meshes (default $FQ_MESH_DIR, else ../shared/meshes)");
  fq::client::add_ranged(app, "--streams", a.streams, "concurrent streams", 1, 256);
  fq::client::add_ranged(app, "--fps", a.producer.fps, "frames per second per stream", 0.01, 10000.0);
  fq::client::add_defaulted(app, "-d,--duration", a.producer.seconds, "seconds of sending per stream");
  fq::client::add_defaulted(app, "--warmup", a.warmup, "first seconds not measured");
  fq::client::add_defaulted(app, "--drain", a.drain, "longest wait for the last results");
  fq::client::add_ranged(app, "--chunks", a.producer.spec.chunks, "Draco chunks per frame", 1, 256);
  fq::client::add_defaulted(app, "--phases", a.phases,
                            "aligned: every stream sends at the same instants (cameras on one sync signal); "
                            "spread: stream i sends i/K of a frame period later (free-running cameras)")
      ->check(CLI::IsMember({"aligned", "spread"}));
  fq::client::add_ranged(app, "--encode-speed", a.encode_speed,
                         "Draco encoder speed 0..10 of the producers and of fqd's results (in-process fqd)",
                         0, 10);
  app.add_option("--result-form", a.result_form,
                 "positions | mesh: the results of the in-process fqd (default: its config's)")
      ->check(CLI::IsMember({"positions", "mesh"}));
  fq::client::add_defaulted(app, "--noise", a.producer.noise, "noise in mean edges (0 = the mesh as is)");
  fq::client::add_defaulted(app, "--variants", a.producer.variants, "distinct noisy frames per stream");
  app.add_option("--budget-ms", a.budget_ms,
                 "latency budget of the streams (in-process fqd; 0 = default/config)");
  fq::client::add_defaulted(
      app, "--engine", a.engine,
      "in-process engine: auto | cuda | cpu | copy (returns its input: fqd's host path alone)");
  app.add_option("--gpus", a.gpus, "GPUs of the in-process fqd, one engine each (e.g. 0,1)")->delimiter(',');
  app.add_option("--cpu-threads", a.cpu_threads, "CPU engine threads (0 = all)");
  fq::client::add_defaulted(
      app, "--decode-threads", a.decode_threads,
      "fqd decode workers, frames decoded at once (0 = half the hardware threads, at least 2)");
  fq::client::add_defaulted(
      app, "--encode-threads", a.encode_threads,
      "fqd encode workers, results encoded at once (0 = half the hardware threads, at least 2)");
  app.add_option(
      "--config", a.config,
      "in-process fqd from this config file (its endpoints are replaced; no HTTP, no stats lines)");
  app.add_flag("--connect", a.connect, "benchmark a running fqd at --ingest, --publish, --control");
  app.add_option("--ingest", a.ingest, "running fqd's ingest endpoint");
  app.add_option("--publish", a.publish, "running fqd's publish endpoint");
  app.add_option("--control", a.control, "running fqd's control endpoint");
  fq::client::add_defaulted(app, "--stream-prefix", a.stream_prefix,
                            "stream ids are <prefix>0, <prefix>1, ...");
  app.add_flag("--decode", a.decode, "decode and check every result (costs consumer CPU)");
  app.add_flag("--json", a.json, "print the report as JSON");
  app.add_flag("--markdown", a.markdown, "also print a docs/BENCHMARKS.md table row");
  fq::client::add_override_options(app, a.overrides);
}

// The tool, once the command line has filled `a`.
int run(Args& a) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("fqd"));  // stdout carries the report
  spdlog::set_level(spdlog::level::warn);
  auto fail = [](const fq::Status& s) {
    std::fprintf(stderr, "fqstreambench: %s\n", s.message().c_str());
    return 1;
  };
  a.producer.spec.encode_speed = a.producer.spec.decode_speed = a.encode_speed;
  if (fq::Status s = fq::client::to_wire(a.overrides, a.producer.spec.overrides, a.producer.spec.compute);
      !s.ok())
    return fail(s);
  fq::Mesh mesh;
  if (fq::Status s = fq::io::read_mesh(resolve_mesh(a), mesh); !s.ok()) return fail(s);

  fq::bench::RunInfo run;
  run.mesh_name = std::filesystem::path(a.mesh).filename().string();
  run.vertices = mesh.num_vertices(), run.triangles = mesh.num_triangles();
  run.streams = a.streams, run.fps = a.producer.fps, run.seconds = a.producer.seconds, run.warmup = a.warmup;
  run.chunks = a.producer.spec.chunks;
  run.phases = a.phases;
  std::unique_ptr<fq::daemon::Daemon> daemon;
  Endpoints ep{a.ingest, a.publish, a.control};
  if (a.connect) {
    if (a.ingest.empty() || a.publish.empty() || a.control.empty())
      return fail(fq::invalid_argument("--connect needs --ingest, --publish and --control"));
    run.engine = "external fqd";
  } else if (fq::Status s = start_daemon(a, daemon, ep, run.engine); !s.ok()) {
    return fail(s);
  }
  if (fq::Status s = run_streams(a, mesh, ep, daemon.get(), run); !s.ok()) return fail(s);
  if (daemon) daemon->stop();
  if (a.json)
    std::printf("%s\n", fq::bench::report_json(run).dump(2).c_str());
  else
    std::printf("%s", fq::bench::report_text(run).c_str());
  if (a.markdown)
    std::printf("%s\n%s\n", fq::bench::report_markdown_header().c_str(),
                fq::bench::report_markdown_row(run).c_str());
  return run.overall.results() > 0 && run.overall.bad() == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  return fq::client::args_main("fqstreambench",
                               "fqstreambench: latency and throughput of fqd at a sustained frame rate",
                               add_options, run, argc, argv);
}
