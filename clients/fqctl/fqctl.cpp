// fqctl: operates a running fqd over its control socket.
//   fqctl [--control EP] streams | params STREAM | set [--create] STREAM key=value… |
//         counters [STREAM] | watch [STREAM]      (each with --json)
// Exit status: 0 done; 1 fqd did not answer in time or refused the request (an unknown stream
// included; one line on stderr says which); 2 bad command line (an unknown key included).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>

#include "clients/common/control_client.h"
#include "clients/common/curve_options.h"
#include "clients/common/tool_app.h"
#include "clients/fqctl/counters_table.h"
#include "clients/fqctl/param_assign.h"
#include "common/tool_main.h"
#include "daemon/control/counters_json.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct Args {
  std::string control = "tcp://127.0.0.1:5557", stream;
  std::vector<std::string> assignments;
  int timeout_ms = 2000, count = 0;
  double interval = 1.0;
  bool json = false, create = false;
  fq::client::CurveClientOptions curve;
};

// One request on a fresh REQ socket (a REQ socket is unusable after a timeout). A missing
// fqd shows as a timeout: ZeroMQ connects lazily, so there is no refused connection to see.
fq::Status call(const Args& a, const fq::wire::ControlRequest& q, fq::wire::ControlReply& reply) {
  zmq::context_t ctx(1);
  zmq::socket_t req(ctx, zmq::socket_type::req);
  req.set(zmq::sockopt::linger, 0);
  FQ_RETURN_IF_ERROR(fq::client::apply_curve_client(req, a.curve));
  try {
    req.connect(a.control);
  } catch (const zmq::error_t& e) {
    return fq::invalid_argument("bad control endpoint " + a.control + ": " + e.what());
  }
  fq::Status s = fq::client::control_call(req, q, reply, a.timeout_ms);
  if (s.code() == fq::StatusCode::kUnavailable)
    return {s.code(), "no reply from fqd at " + a.control + " within " + std::to_string(a.timeout_ms) +
                          " ms (is fqd running, and is that its control endpoint?)"};
  return s;
}

int fail(const fq::Status& s) {
  std::fprintf(stderr, "fqctl: %s\n", s.message().c_str());
  return 1;
}

int cmd_streams(const Args& a) {
  fq::wire::ControlRequest q;
  q.mutable_list_streams();
  fq::wire::ControlReply r;
  if (fq::Status s = call(a, q, r); !s.ok()) return fail(s);
  if (a.json) {
    std::printf("%s\n", nlohmann::json{{"streams", r.streams()}}.dump(2).c_str());
    return 0;
  }
  for (const std::string& id : r.streams()) std::printf("%s\n", id.c_str());
  return 0;
}

/// A parameter's value as JSON: numbers and booleans as such, names as strings.
nlohmann::json json_value(const std::string& text) {
  const nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  return parsed.is_number() || parsed.is_boolean() ? parsed : nlohmann::json(text);
}

int print_params(const Args& a, const fq::wire::ControlReply& r) {
  const auto params = fq::client::describe_params(r);
  if (a.json) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [key, value] : params) j[key] = json_value(value);
    std::printf("%s\n", nlohmann::json{{"stream", a.stream}, {"params", j}}.dump(2).c_str());
    return 0;
  }
  for (const auto& [key, value] : params) std::printf("%s = %s\n", key.c_str(), value.c_str());
  return 0;
}

int cmd_params(const Args& a) {
  fq::wire::ControlRequest q;
  q.mutable_get_params()->set_stream_id(a.stream);
  fq::wire::ControlReply r;
  if (fq::Status s = call(a, q, r); !s.ok()) return fail(s);
  return print_params(a, r);
}

int cmd_set(const Args& a) {
  fq::wire::ControlRequest q;
  fq::wire::SetParams* set = q.mutable_set_params();
  set->set_stream_id(a.stream);
  if (a.create) set->set_create(true);
  for (const std::string& kv : a.assignments) {
    if (fq::Status s = fq::client::assign_param(kv, *set); !s.ok()) {
      std::fprintf(stderr, "fqctl: %s\n", s.message().c_str());
      return 2;
    }
  }
  fq::wire::ControlReply r;
  if (fq::Status s = call(a, q, r); !s.ok()) return fail(s);
  return print_params(a, r);
}

fq::Status get_counters(const Args& a, fq::wire::ControlReply& r) {
  fq::wire::ControlRequest q;
  q.mutable_get_counters()->set_stream_id(a.stream);
  return call(a, q, r);
}

int cmd_counters(const Args& a) {
  fq::wire::ControlReply r;
  if (fq::Status s = get_counters(a, r); !s.ok()) return fail(s);
  if (a.json) {
    std::printf("%s\n", fq::daemon::counters_json(r).dump(2).c_str());
    return 0;
  }
  fq::client::OutCounts none;
  std::printf("%s", fq::client::counters_table(r, 0.0, none).c_str());
  return 0;
}

int cmd_watch(const Args& a) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const bool tty = isatty(STDOUT_FILENO);
  fq::client::OutCounts previous;
  auto last = std::chrono::steady_clock::now();
  for (int n = 0; !g_stop && (a.count == 0 || n < a.count); ++n) {
    if (n > 0) std::this_thread::sleep_for(std::chrono::duration<double>(a.interval));
    fq::wire::ControlReply r;
    if (fq::Status s = get_counters(a, r); !s.ok()) return fail(s);
    const auto now = std::chrono::steady_clock::now();
    const double seconds = n == 0 ? 0.0 : std::chrono::duration<double>(now - last).count();
    last = now;
    if (a.json) {  // one object a line: {"interval_s", "streams": [... each with "fps"]}
      nlohmann::json j = fq::daemon::counters_json(r);
      for (nlohmann::json& c : j["streams"]) {
        const auto it = previous.find(c["stream"].get<std::string>());
        c["fps"] = it == previous.end() || seconds <= 0
                       ? nlohmann::json()
                       : nlohmann::json((c["frames_out"].get<double>() - double(it->second)) / seconds);
        previous[c["stream"].get<std::string>()] = c["frames_out"].get<uint64_t>();
      }
      j["interval_s"] = seconds;
      std::printf("%s\n", j.dump().c_str());
      std::fflush(stdout);
      continue;
    }
    // On a terminal the table is redrawn in place; piped, refreshes follow each other.
    std::printf("%s%s\n", tty ? "\033[H\033[2J" : "",
                fq::client::counters_table(r, seconds, previous).c_str());
    std::fflush(stdout);
  }
  return 0;
}

int run(int argc, char** argv) {
  fq::client::ToolApp app{"fqctl: inspect and steer a running fqd through its control socket", "fqctl"};
  Args a;
  app.add_option("-c,--control", a.control, "fqd's control endpoint")->capture_default_str();
  fq::client::add_curve_options(app, a.curve);
  app.add_option("--timeout-ms", a.timeout_ms, "how long to wait for fqd's reply")
      ->capture_default_str()
      ->check(CLI::Range(1, 600000));
  app.require_subcommand(1);
  app.add_subcommand("streams", "list the streams fqd knows (configured or seen)");
  CLI::App* params = app.add_subcommand("params", "print a stream's current parameters");
  params->add_option("stream", a.stream, "stream id")->required();
  CLI::App* set = app.add_subcommand("set", "change a stream's parameters from its next frame on");
  set->add_option("stream", a.stream,
                  "stream id: one fqd knows (configured or seen), or a new one with --create")
      ->required();
  set->add_flag("--create", a.create,
                "make the stream when fqd does not know it (without it, an unknown id is refused, naming the "
                "nearest known one)");
  set->add_option("assignments", a.assignments,
                  "key=value, e.g. sigma_s=3 mode=bf compute=filter result_form=mesh")
      ->required();
  CLI::App* counters = app.add_subcommand("counters", "frame counters and stage latencies");
  counters->add_option("stream", a.stream, "one stream (default: all)");
  CLI::App* watch = app.add_subcommand("watch", "live tables: fps, drops, late, errors; p50/p99 per stage");
  watch->add_option("stream", a.stream, "one stream (default: all)");
  watch->add_option("-i,--interval", a.interval, "seconds between refreshes")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 3600.0));
  watch->add_option("-n,--count", a.count, "stop after this many refreshes (0 = until Ctrl-C)");
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    sub->add_flag("--json", a.json,
                  sub == watch ? "one JSON object a refresh, each stream with its fps (JSON lines)"
                               : "JSON on stdout (counters: the words of fqd's /metrics, \"frames_in\": N)");
  CLI11_PARSE(app, argc, argv);

  if (*set) return cmd_set(a);
  if (*params) return cmd_params(a);
  if (*counters) return cmd_counters(a);
  if (*watch) return cmd_watch(a);
  return cmd_streams(a);
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqctl", run, argc, argv); }
