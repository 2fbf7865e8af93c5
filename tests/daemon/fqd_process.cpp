#include "tests/daemon/fqd_process.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

namespace fq::test {
namespace {

// True once `pid` has exited (a zombie not yet reaped still answers kill(pid, 0)).
bool exited(pid_t pid) {
  siginfo_t info{};
  return waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid;
}

}  // namespace

std::string ops_config(const std::string& extra) {
  std::ifstream in(std::string(FQ_SOURCE_DIR) + "/tests/daemon/child_fqd.toml");
  std::string base((std::istreambuf_iterator<char>(in)), {});
  EXPECT_FALSE(base.empty()) << "tests/daemon/child_fqd.toml is missing";
  return base + "\n" + extra;
}

std::string http_without_viewer(const std::string& listen) {
  const std::filesystem::path empty = std::filesystem::path(testing::TempDir()) / "fq_no_viewer";
  std::filesystem::create_directories(empty);
  return "[http]\nlisten = \"" + listen + "\"\nweb_root = \"" + empty.string() + "\"\n";
}

std::string write_temp_file(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

std::string shell_words(const std::string& path, const std::vector<std::string>& args) {
  std::string command = "'" + path + "'";
  for (const std::string& a : args) command += " '" + a + "'";
  return command;
}

FqdProcess::FqdProcess(const std::vector<std::string>& args, const std::string& prefix,
                       const std::string& suffix) {
  std::vector<std::string> all = args;
  all.push_back("--print-endpoints");
  child_ = prefix.empty() && suffix.empty()
               ? spawn(FQD_PATH, all)
               : spawn("/bin/sh", {"-c", prefix + " exec " + shell_words(FQD_PATH, all) + " " + suffix});
  char line[2048] = {0};
  if (child_.out && std::fgets(line, sizeof line, child_.out)) {
    endpoints_ = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!endpoints_.is_object()) endpoints_ = nlohmann::json::object();
  }
}

FqdProcess::~FqdProcess() { stop(); }

bool FqdProcess::alive() const {
  return status_ == -2 && child_.pid > 0 && kill(child_.pid, 0) == 0 && !exited(child_.pid);
}

int FqdProcess::stop() {
  if (status_ != -2 || child_.pid <= 0) return status_;
  kill(child_.pid, SIGTERM);
  status_ = wait_exit(child_.pid);
  if (child_.out) std::fclose(child_.out);
  child_.out = nullptr;
  return status_;
}

ToolRun run_tool(const std::string& path, const std::vector<std::string>& args, int seconds) {
  // stderr joins stdout through the shell, so that one-line error messages can be checked.
  // coreutils timeout ends a tool that hangs, so the test reports instead of waiting forever.
  const std::string command =
      "exec timeout -k 5 " + std::to_string(seconds) + " " + shell_words(path, args) + " 2>&1";
  Child c = spawn("/bin/sh", {"-c", command});
  ToolRun run;
  if (c.pid <= 0) return run;
  run.output = read_all(c.out);
  std::fclose(c.out);
  run.status = wait_exit(c.pid, seconds + 10);
  return run;
}

ToolRun publish_fandisk(const std::string& ingest, const std::string& stream, int count, int fps) {
  return run_tool(FQPUB_PATH, {std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply", "--endpoint", ingest,
                               "--stream", stream, "--fps", std::to_string(fps), "--count",
                               std::to_string(count), "--noise", "0.1", "--quiet"});
}

}  // namespace fq::test
