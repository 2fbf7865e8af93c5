// fqpub: publishes a mesh file, or a folder of meshes as a looped sequence, to fqd's ingest
// endpoint at a fixed frame rate, optionally with fresh noise each frame.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "clients/common/curve_options.h"
#include "clients/common/defaulted_option.h"
#include "clients/common/frame_sender.h"
#include "clients/common/mesh_source.h"
#include "clients/common/override_options.h"
#include "clients/common/peer_monitor.h"
#include "clients/common/tool_app.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct Args {
  std::string input, endpoint = "tcp://127.0.0.1:5555", bind_pub;
  fq::client::CurveClientOptions curve;
  double fps = 10.0, noise = 0.0, duration = 0.0;
  uint64_t seed = 1, count = 0;
  bool json = false, quiet = false;
  fq::client::FrameSpec spec = [] {
    fq::client::FrameSpec s;
    s.chunks = 0;  // by the frame's size
    return s;
  }();
  fq::client::OverrideArgs overrides;
};

struct Totals {
  uint64_t sent = 0;
  uint64_t unconnected = 0;  ///< of them, sent while no fqd was connected
  double encode_ms = 0.0;
  double seconds = 0.0;
  bool failed = false;
};

// How long fqpub gives fqd to connect before it says that none is there.
constexpr int kConnectGraceMs = 1000;

// Says once when frames go out with no fqd connected, and again when one connects.
// Whether the progress line is redrawn in place (a terminal, not --quiet or --json): the lines
// after it then start on a line of their own; in a log file there is no progress line.
bool redraws(const Args& a) { return !a.quiet && !a.json && isatty(STDERR_FILENO); }
const char* after_progress(const Args& a) { return redraws(a) ? "\n" : ""; }

void report_peer(const Args& a, const fq::client::PeerMonitor& monitor, bool& warned) {
  const bool pub = !a.bind_pub.empty();
  if (monitor.peers() == 0 && !warned) {
    std::fprintf(
        stderr, "%sfqpub: no fqd connected %s %s: %s\n", after_progress(a),
        pub ? "to our PUB socket at" : "at", (pub ? a.bind_pub : a.endpoint).c_str(),
        pub ? "frames are dropped until one subscribes" : "frames wait in the queue until one connects");
    warned = true;
  } else if (monitor.peers() > 0 && warned) {
    std::fprintf(stderr, "%sfqpub: fqd connected\n", after_progress(a));
    warned = false;
  }
}

// Sends frames until --count, --duration or a signal; returns the totals.
Totals publish(const Args& a, const fq::client::MeshSource& source, zmq::socket_t& push,
               fq::client::PeerMonitor& monitor) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const auto period = std::chrono::duration<double>(1.0 / a.fps);
  Totals t;
  std::vector<std::vector<std::string>> cached(source.size());  // noiseless frames encode once
  fq::Mesh scratch;
  auto last_send = start;
  bool warned = false;
  for (uint64_t i = 0; !g_stop && (a.count == 0 || i < a.count); ++i) {
    const auto due = start + std::chrono::duration_cast<clock::duration>(period * static_cast<double>(i));
    if (a.duration > 0 && std::chrono::duration<double>(due - start).count() >= a.duration) break;
    std::this_thread::sleep_until(due);  // pacing the frame rate, not synchronization
    const auto t0 = clock::now();
    std::vector<std::string> parts;
    std::vector<std::string>& slot = cached[i % source.size()];
    if (a.noise > 0 || slot.empty()) {
      const fq::Mesh& m = source.frame(i, a.noise, a.seed, scratch);
      if (fq::Status s = fq::client::build_frame(m.view(), a.spec, i, parts); !s.ok()) {
        std::fprintf(stderr, "fqpub: cannot encode %s: %s\n", source.name(i).c_str(), s.message().c_str());
        t.failed = true;
        break;
      }
      if (a.noise <= 0) slot = parts;
    } else {
      parts = slot;
      fq::client::restamp_frame(parts, i);
    }
    t.encode_ms += std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    monitor.poll();
    if (monitor.refused()) {  // a PUSH socket would wait for a peer that never comes
      t.failed = true;
      break;
    }
    report_peer(a, monitor, warned);
    if (monitor.peers() == 0) ++t.unconnected;
    fq::client::send_parts(push, parts);
    last_send = clock::now();
    ++t.sent;
    // A line redrawn in place on a terminal; in a log file it would be one line per frame.
    if (redraws(a))
      std::fprintf(stderr, "\rfqpub: sent %llu frames", static_cast<unsigned long long>(t.sent));
  }
  t.seconds = std::chrono::duration<double>(last_send - start).count();
  return t;
}

// Frames 0..n-1 go out at t = 0, 1/fps, ...: n - 1 periods between the first and the last.
double fps_of(const Totals& t) {
  return t.sent > 1 && t.seconds > 0 ? static_cast<double>(t.sent - 1) / t.seconds : 0.0;
}

nlohmann::json summary(const Args& a, const Totals& t, bool connected) {
  return {{"stream", a.spec.stream_id},
          {"frames_sent", t.sent},
          {"frames_sent_unconnected", t.unconnected},
          {"chunks", a.spec.chunks == 0 ? "auto" : std::to_string(a.spec.chunks)},
          {"fqd_connected", connected},
          {"seconds", t.seconds},
          {"fps", fps_of(t)},
          {"encode_ms_mean", t.sent ? t.encode_ms / static_cast<double>(t.sent) : 0.0}};
}

// Every command-line option, into `a`.
void add_options(CLI::App& app, Args& a) {
  app.add_option("input", a.input, "mesh file (.ply .obj .stl .drc) or folder of them")->required();
  fq::client::add_defaulted(app, "-e,--endpoint", a.endpoint, "fqd ingest endpoint (PUSH connects)");
  app.add_option("--bind-pub", a.bind_pub,
                 "bind a PUB socket here instead (fqd SUB-connects: [ingest] connect); frames sent "
                 "while no fqd is subscribed are dropped");
  fq::client::add_defaulted(app, "-s,--stream", a.spec.stream_id, "stream id (the topic of the results)");
  fq::client::add_ranged(app, "--fps", a.fps, "frames per second", 0.001, 10000.0);
  fq::client::add_ranged(
      app, "--chunks", a.spec.chunks,
      "Draco chunks per frame; 0: one per 16,384 vertices, at most 16 (fqd decodes a frame's "
      "chunks at once)",
      0, 256);
  fq::client::add_ranged(app, "--position-bits", a.spec.position_bits, "Draco position bits", 8, 30);
  fq::client::add_ranged(app, "--encode-speed", a.spec.encode_speed,
                         "Draco encoder speed 0..10 (10: fastest, largest)", 0, 10);
  app.add_option("--noise", a.noise, "Gaussian noise per frame, in mean edge lengths (0 = none)")
      ->check(CLI::Range(0.0, 100.0));
  fq::client::add_defaulted(app, "--seed", a.seed, "noise seed (frame i uses seed + i)");
  app.add_option("-n,--count", a.count, "frames to send (0 = until --duration or Ctrl-C)");
  app.add_option("-d,--duration", a.duration, "seconds to publish (0 = until --count or Ctrl-C)");
  fq::client::add_curve_options(app, a.curve);
  app.add_flag("--json", a.json, "print the summary as JSON");
  app.add_flag("-q,--quiet", a.quiet, "no progress line");
  fq::client::add_override_options(app, a.overrides);
}

// The tool, once the command line has filled `a`.
int run(Args& a) {
  a.spec.decode_speed = a.spec.encode_speed;
  if (fq::Status s = fq::client::to_wire(a.overrides, a.spec.overrides, a.spec.compute); !s.ok()) {
    std::fprintf(stderr, "fqpub: %s\n", s.message().c_str());
    return 2;
  }
  fq::client::MeshSource source;
  if (fq::Status s = source.open(a.input); !s.ok()) {
    std::fprintf(stderr, "fqpub: %s\n", s.message().c_str());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  zmq::context_t ctx(1);
  const bool pub = !a.bind_pub.empty();
  zmq::socket_t push(ctx, pub ? zmq::socket_type::pub : zmq::socket_type::push);
  push.set(zmq::sockopt::linger, 5000);  // deliver queued frames before exiting
  if (fq::Status s = fq::client::apply_curve_client(push, a.curve); !s.ok()) {
    std::fprintf(stderr, "fqpub: %s\n", s.message().c_str());
    return 2;
  }
  auto monitor = std::make_unique<fq::client::PeerMonitor>(push, std::to_string(::getpid()));
  try {
    if (pub)
      push.bind(a.bind_pub);
    else
      push.connect(a.endpoint);
  } catch (const zmq::error_t& e) {
    const std::string& ep = pub ? a.bind_pub : a.endpoint;
    std::fprintf(stderr, "fqpub: cannot %s %s: %s\n", pub ? "bind" : "connect to", ep.c_str(), e.what());
    return 2;
  }
  monitor->wait_for_peer(kConnectGraceMs);
  const Totals t = monitor->refused() ? Totals{0, 0, 0.0, 0.0, true} : publish(a, source, push, *monitor);
  monitor->poll();
  const bool connected = monitor->ever_connected();
  if (monitor->refused()) {
    std::fprintf(stderr,
                 "%sfqpub: fqd at %s refused our CURVE key (ZAP status %d): add our public key to fqd's "
                 "[security] client_keys_file, or check --server-key and --key-file\n",
                 after_progress(a), monitor->refused_by().c_str(), monitor->refused_status());
    monitor.reset();
    push.set(zmq::sockopt::linger, 0);  // nothing can be delivered: do not wait for it
    push.close();
    if (a.json) std::printf("%s\n", summary(a, t, connected).dump().c_str());
    return 1;
  }
  monitor.reset();  // before the socket closes (see peer_monitor.h)
  if (!connected) {
    push.set(zmq::sockopt::linger, 0);  // nothing can be delivered: do not wait for it
    std::fprintf(stderr, "fqpub: no fqd ever connected: none of the %llu frames reached one\n",
                 static_cast<unsigned long long>(t.sent));
  }
  push.close();
  if (t.failed || t.sent == 0 || !connected) {
    if (a.json) std::printf("%s\n", summary(a, t, connected).dump().c_str());
    return 1;
  }
  if (a.json) {
    std::printf("%s\n", summary(a, t, connected).dump().c_str());
  } else {
    std::fprintf(stderr, "%sfqpub: stream '%s': %llu frames in %.2f s (%.1f fps), encode %.2f ms/frame\n",
                 after_progress(a), a.spec.stream_id.c_str(), static_cast<unsigned long long>(t.sent),
                 t.seconds, fps_of(t), t.sent ? t.encode_ms / static_cast<double>(t.sent) : 0.0);
    if (t.unconnected > 0)
      std::fprintf(stderr, "fqpub: %llu of them were sent while no fqd was connected\n",
                   static_cast<unsigned long long>(t.unconnected));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return fq::client::args_main("fqpub",
                               "fqpub: publish mesh frames to fqd (a file, or a folder as a looped sequence)",
                               add_options, run, argc, argv);
}
