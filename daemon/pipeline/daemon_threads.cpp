#include "daemon/pipeline/daemon_threads.h"

#include <pthread.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "daemon/pipeline/process_stats.h"

namespace fq::daemon {
namespace {

std::string first_line(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  return line;
}

// A thread's CPU seconds: schedstat's first field is its time on a CPU in ns; without
// schedstats (a kernel built without them), utime + stime from stat, in clock ticks.
double thread_cpu_seconds(const std::filesystem::path& task) {
  std::ifstream sched(task / "schedstat");
  double ns = 0;
  if (sched >> ns) return ns * 1e-9;
  // A thread's stat has its process's layout.
  return parse_proc_stat(first_line(task / "stat"), sysconf(_SC_CLK_TCK), sysconf(_SC_PAGESIZE), 0)
      .cpu_seconds;
}

}  // namespace

void name_this_thread(const char* role) {
  const std::string name = std::string("fqd-") + role;
  pthread_setname_np(pthread_self(), name.substr(0, 15).c_str());
}

void tag_zmq_threads(zmq::context_t& ctx) { ctx.set(zmq::ctxopt::thread_name_prefix, kZmqThreadTag); }

bool is_daemon_thread(std::string_view name) {
  static const std::string zmq_prefix = std::to_string(kZmqThreadTag) + "/ZMQbg";
  return name.substr(0, 4) == "fqd-" || name == "fq-pool" || name.substr(0, zmq_prefix.size()) == zmq_prefix;
}

double daemon_threads_cpu_seconds() {
  double total = 0;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec))
    if (is_daemon_thread(first_line(task.path() / "comm"))) total += thread_cpu_seconds(task.path());
  return total;
}

}  // namespace fq::daemon
