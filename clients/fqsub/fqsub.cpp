// fqsub: subscribes to fqd's results, decodes and checks each, writes every Nth as a PLY
// with cluster colours, shows a live status line and prints a summary (drops by reason: --help).
// Results in the POSITIONS form take their faces from --faces (the mesh the producer sent).
// Exit status: 0 when every result decoded, passed the checks and was not an error result,
// and at least one came (or Ctrl-C / SIGTERM ended the run: stopping it is no failure);
// 1 otherwise; 2 for bad options.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "clients/common/curve_options.h"
#include "clients/common/result_receiver.h"
#include "clients/common/stream_stats.h"
#include "clients/common/tool_app.h"
#include "common/tool_main.h"
#include "io/mesh_io.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct Args {
  std::string endpoint = "tcp://127.0.0.1:5556", out_dir, faces_file;
  fq::client::CurveClientOptions curve;
  std::vector<uint32_t> faces;  ///< triangles of --faces
  std::vector<std::string> streams;
  uint64_t count = 0, write_every = 0;
  double duration = 0.0, idle_timeout = 0.0;
  int decode_threads = 2;
  bool json = false, quiet = false;
};

// Sequence numbers in file names have at least this many digits, so that names sort in frame
// order (cam0_0000000020.ply before cam0_0000000101.ply) for 10^10 frames, 10 years at 30 fps.
constexpr int kSequenceDigits = 10;

// Writes one result as <out>/<stream>_<sequence>.ply; returns the path or "" on failure.
std::string write_ply(const Args& a, const fq::client::ReceivedResult& r) {
  char sequence[32];
  std::snprintf(sequence, sizeof sequence, "%0*llu", kSequenceDigits,
                static_cast<unsigned long long>(r.header.sequence()));
  std::string path =
      (std::filesystem::path(a.out_dir) / (r.header.stream_id() + "_" + sequence + ".ply")).string();
  if (r.mesh.num_triangles() == 0) {
    std::fprintf(stderr,
                 "\nfqsub: result carries positions only: pass --faces with the mesh the producer sent, "
                 "or set the stream's output.result_form = \"mesh\"\n");
    return "";
  }
  const uint32_t* labels = r.labels.empty() ? nullptr : r.labels.data();
  if (fq::Status s = fq::io::write_mesh(path, r.mesh.view(), labels, r.header.cluster_count()); !s.ok()) {
    std::fprintf(stderr, "\nfqsub: %s\n", s.message().c_str());
    return "";
  }
  return path;
}

// Decodes and checks one result, logging what is wrong; true when it is good.
bool inspect(const Args& a, fq::client::ReceivedResult& r, fq::Status why) {
  if (why.ok()) why = fq::client::decode_result(r, a.decode_threads, a.faces.empty() ? nullptr : &a.faces);
  if (why.ok()) why = fq::client::check_result(r);
  if (!why.ok())
    std::fprintf(stderr, "\nfqsub: bad result from stream '%s' frame %llu: %s\n", r.topic.c_str(),
                 static_cast<unsigned long long>(r.header.sequence()), why.message().c_str());
  else if (r.header.status() == fq::wire::ERROR)
    std::fprintf(stderr, "\nfqsub: error result for stream '%s' frame %llu: %s\n",
                 r.header.stream_id().c_str(), static_cast<unsigned long long>(r.header.sequence()),
                 r.header.error().c_str());
  return why.ok();
}

// Subscribes and connects; false (with a message) for a bad endpoint.
bool subscribe(const Args& a, zmq::socket_t& sub) {
  sub.set(zmq::sockopt::rcvtimeo, 200);  // wake up for the status line and the time limits
  sub.set(zmq::sockopt::rcvhwm, 100000);
  if (fq::Status s = fq::client::apply_curve_client(sub, a.curve); !s.ok()) {
    std::fprintf(stderr, "fqsub: %s\n", s.message().c_str());
    return false;
  }
  if (a.streams.empty()) sub.set(zmq::sockopt::subscribe, "");
  // ZeroMQ topics are prefixes: receive_loop's exact-match check drops e.g. "cam10" for "cam1".
  for (const std::string& s : a.streams) sub.set(zmq::sockopt::subscribe, s);
  try {
    sub.connect(a.endpoint);
  } catch (const zmq::error_t& e) {
    std::fprintf(stderr, "fqsub: cannot connect to %s: %s\n", a.endpoint.c_str(), e.what());
    return false;
  }
  return true;
}

// Receives until a limit or a signal; returns the path of the last PLY written.
std::string receive_loop(const Args& a, zmq::socket_t& sub, fq::client::StreamStats& stats) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_result = start, last_line = start;
  std::string last_ply;
  uint64_t good = 0;
  while (!g_stop && (a.count == 0 || stats.results() < a.count)) {
    const auto now = clock::now();
    if (a.duration > 0 && std::chrono::duration<double>(now - start).count() >= a.duration) break;
    if (a.idle_timeout > 0 && std::chrono::duration<double>(now - last_result).count() >= a.idle_timeout)
      break;
    // Redrawn in place on a terminal; a log file gets only the closing line.
    if (!a.quiet && !a.json && isatty(STDERR_FILENO) && now - last_line >= std::chrono::seconds(1)) {
      std::fprintf(stderr, "\rfqsub: %s", stats.status_line().c_str());
      last_line = now;
    }
    fq::client::ReceivedResult r;
    fq::StatusOr<bool> got = false;
    try {
      got = fq::client::receive_result(sub, r);
    } catch (const zmq::error_t& e) {
      if (e.num() == EINTR) continue;  // a signal (Ctrl-C) interrupted the wait: g_stop says why
      throw;
    }
    if (fq::client::timed_out(got)) continue;
    if (!a.streams.empty() && std::find(a.streams.begin(), a.streams.end(), r.topic) == a.streams.end())
      continue;
    last_result = clock::now();
    const bool ok = inspect(a, r, got.status());
    stats.add(r, ok);
    if (ok && r.header.status() != fq::wire::ERROR && a.write_every > 0 && good++ % a.write_every == 0) {
      if (std::string p = write_ply(a, r); !p.empty()) last_ply = p;
    }
  }
  return last_ply;
}

int run(int argc, char** argv) {
  fq::client::ToolApp app{"fqsub: receive, check and save fqd results", "fqsub"};
  Args a;
  app.add_option("-e,--endpoint", a.endpoint, "fqd publish endpoint (SUB connects)")->capture_default_str();
  app.add_option("-s,--stream", a.streams, "stream id to subscribe to (repeatable; none = all streams)");
  app.add_option("-n,--count", a.count, "stop after this many results (0 = no limit)");
  app.add_option("-d,--duration", a.duration, "stop after this many seconds (0 = no limit)");
  fq::client::add_curve_options(app, a.curve);
  app.add_option("--idle-timeout", a.idle_timeout,
                 "stop when no result came for this many seconds (0 = never)");
  app.add_option("--write-every", a.write_every, "write every Nth good result as PLY (0 = none)");
  app.add_option("-o,--out", a.out_dir, "folder for the PLY files");
  app.add_option("--faces", a.faces_file,
                 "mesh file whose faces POSITIONS-form results reuse (the mesh the producer sent)");
  app.add_option("--decode-threads", a.decode_threads, "threads decoding a result's chunks")
      ->capture_default_str();
  app.add_flag("--json", a.json, "print the summary as JSON on stdout");
  app.add_flag("-q,--quiet", a.quiet, "no live status line");
  app.footer(
      "Drops, by reason as far as results tell them apart:\n"
      "  gap         sequence numbers of a stream with no result: fqd superseded the frame (a newer one\n"
      "              came while it waited), dropped it stale (older than budget_ms), or this subscriber\n"
      "              missed its result (its queue at fqd was full), or the frame never reached fqd.\n"
      "              fqsub cannot tell these apart; fqd's counters can (fqctl counters STREAM:\n"
      "              superseded, dropped_stale, subscriber_overflows).\n"
      "  preempted   error results: fqd stopped the frame to serve another stream's share of engine time\n"
      "  time_limit  error results: the frame ran past fqd's caps.engine_time_limit_s\n"
      "  stopping    error results: fqd stopped while the frame was on an engine\n");
  CLI11_PARSE(app, argc, argv);
  if (a.write_every > 0 && a.out_dir.empty()) {
    std::fprintf(stderr, "fqsub: --write-every needs --out DIR\n");
    return 2;
  }
  if (!a.faces_file.empty()) {
    fq::Mesh m;
    if (fq::Status s = fq::io::read_mesh(a.faces_file, m); !s.ok()) {
      std::fprintf(stderr, "fqsub: --faces: %s\n", s.message().c_str());
      return 2;
    }
    a.faces = std::move(m.triangles);
  }
  std::error_code ec;
  if (!a.out_dir.empty() && !std::filesystem::create_directories(a.out_dir, ec) && ec) {
    std::fprintf(stderr, "fqsub: cannot create %s: %s\n", a.out_dir.c_str(), ec.message().c_str());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  zmq::context_t ctx(1);
  zmq::socket_t sub(ctx, zmq::socket_type::sub);
  if (!subscribe(a, sub)) return 2;
  fq::client::StreamStats stats;
  const std::string last_ply = receive_loop(a, sub, stats);
  sub.close();
  nlohmann::json j = stats.to_json();
  j["last_ply"] = last_ply;
  if (a.json)
    std::printf("%s\n", j.dump(2).c_str());
  else {
    std::fprintf(stderr, "%sfqsub: %s\n", !a.quiet && isatty(STDERR_FILENO) ? "\r" : "",
                 stats.status_line().c_str());
    if (!last_ply.empty()) std::fprintf(stderr, "fqsub: last PLY written: %s\n", last_ply.c_str());
  }
  const bool enough = stats.results() > 0 || g_stop;  // stopped by the user: no result is no failure
  return enough && stats.bad() == 0 && stats.errors() == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqsub", run, argc, argv); }
