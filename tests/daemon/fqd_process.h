// fqd as a child process for the operations tests, and one-shot runs of the command-line
// tools with their stdout and stderr captured together.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/non_copyable.h"
#include "tests/daemon/child_process.h"

namespace fq::test {

/// tests/daemon/child_fqd.toml (every endpoint on tcp://127.0.0.1:*, the CPU engine on one
/// thread, log level warn, a generous budget) with `extra` appended (more sections).
std::string ops_config(const std::string& extra = "");

/// An [http] section listening on `listen` whose web_root is an empty folder: / answers with how
/// to install the viewer whatever the source tree holds (a web_root the file names must exist).
std::string http_without_viewer(const std::string& listen = "127.0.0.1:0");

/// Writes `text` into the test's temporary folder as `name`; returns the path.
std::string write_temp_file(const std::string& name, const std::string& text);

/// The whole file ("" when it cannot be read).
std::string read_text_file(const std::string& path);

/// Polls `check` every 100 ms for up to 60 s (fqd acts on signals and frames asynchronously).
template <class F>
bool eventually(F check) {
  for (int i = 0; i < 600; ++i) {
    if (check()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

class FqdProcess : NonCopyable {
 public:
  /// Starts fqd with `args` plus --print-endpoints and reads the endpoints line
  /// (endpoints() is empty when fqd printed none, e.g. when it failed to start). With a
  /// `shell` prefix/suffix fqd runs as `/bin/sh -c "<prefix> exec fqd ARGS <suffix>"`
  /// (to set its directory, environment or stderr).
  explicit FqdProcess(const std::vector<std::string>& args, const std::string& prefix = "",
                      const std::string& suffix = "");
  /// SIGTERM, then waits (exit status in stop()).
  ~FqdProcess();

  const nlohmann::json& endpoints() const { return endpoints_; }
  std::string endpoint(const char* role) const { return endpoints_.value(role, ""); }
  pid_t pid() const { return child_.pid; }
  /// True while fqd has not exited.
  bool alive() const;
  /// Sends SIGTERM and returns the exit status (-1 when killed); idempotent.
  int stop();

 private:
  Child child_;
  nlohmann::json endpoints_ = nlohmann::json::object();
  int status_ = -2;
};

struct ToolRun {
  int status = -1;     ///< exit status; 124 past the time limit, -1 when killed by a signal
  std::string output;  ///< stdout and stderr, interleaved
};

/// `path` and `args` single-quoted for /bin/sh.
std::string shell_words(const std::string& path, const std::vector<std::string>& args);

/// Runs `path args…` to completion (killed after `seconds`).
ToolRun run_tool(const std::string& path, const std::vector<std::string>& args, int seconds = 120);

/// Runs fqpub on the bundled data/fandisk.ply: `count` frames at `fps` on `stream`.
ToolRun publish_fandisk(const std::string& ingest, const std::string& stream, int count, int fps = 20);

}  // namespace fq::test
