#include "tests/daemon/child_process.h"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

namespace fq::test {

Child spawn(const std::string& path, const std::vector<std::string>& args) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(fds[1], STDOUT_FILENO);
    close(fds[0]);
    close(fds[1]);
    std::vector<char*> argv{const_cast<char*>(path.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(path.c_str(), argv.data());
    _exit(127);
  }
  close(fds[1]);
  return {pid, fdopen(fds[0], "r")};
}

int wait_exit(pid_t pid, int seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // waiting for exit, not ordering
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_all(FILE* out) {
  std::string s;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, out)) > 0) s.append(buf, n);
  return s;
}

std::string child_fqd_config(const std::string& defaults) {
  return R"(log_level = "warn"
[endpoints]
ingest = "tcp://127.0.0.1:*"
publish = "tcp://127.0.0.1:*"
control = "tcp://127.0.0.1:*"
[engine]
kind = "cpu"
cpu_threads = 1
[defaults]
budget_ms = 60000
)" + defaults;
}

}  // namespace fq::test
