#include "daemon/pipeline/process_stats.h"

#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "daemon/pipeline/prometheus_format.h"

namespace fq::daemon {
namespace {

std::string read_all(const char* path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

double boot_time_seconds() {
  std::istringstream in(read_all("/proc/stat"));
  for (std::string key; in >> key;) {
    if (key == "btime") {
      double t = 0;
      in >> t;
      return t;
    }
    in.ignore(1 << 20, '\n');
  }
  return 0;
}

}  // namespace

ProcessStats parse_proc_stat(const std::string& stat, long ticks, long page, double boot_time) {
  ProcessStats s;
  // The command name (field 2) is in parentheses and may hold spaces and ')': the fields
  // after it start behind the last ')'.
  const size_t close = stat.rfind(')');
  if (close == std::string::npos || ticks <= 0) return s;
  std::istringstream in(stat.substr(close + 1));
  std::vector<std::string> f{"", "", ""};  // fields 1..2 and a placeholder: f[3] is field 3 (state)
  for (std::string w; in >> w;) f.push_back(w);
  if (f.size() <= 24) return s;
  const auto num = [&](size_t i) { return std::stod(f[i]); };
  s.cpu_seconds = (num(14) + num(15)) / static_cast<double>(ticks);  // utime + stime
  s.threads = static_cast<uint64_t>(num(20));
  s.start_time_seconds = boot_time + num(22) / static_cast<double>(ticks);
  s.virtual_bytes = static_cast<uint64_t>(num(23));
  s.resident_bytes = static_cast<uint64_t>(num(24)) * static_cast<uint64_t>(page);
  s.ok = true;
  return s;
}

ProcessStats read_process_stats() {
  ProcessStats s = parse_proc_stat(read_all("/proc/self/stat"), sysconf(_SC_CLK_TCK), sysconf(_SC_PAGESIZE),
                                   boot_time_seconds());
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++s.open_fds;
  rlimit lim{};
  if (getrlimit(RLIMIT_NOFILE, &lim) == 0) s.max_fds = lim.rlim_cur;
  return s;
}

std::string process_metrics_text(const ProcessStats& s) {
  std::string out;
  if (!s.ok) return out;
  const auto one = [&](const char* name, const char* type, const char* help, double v) {
    append_family(out, name, type, help);
    out += std::string(name) + " " + metric_number(v) + "\n";
  };
  one("process_cpu_seconds_total", "counter", "Total user and system CPU time spent in seconds.",
      s.cpu_seconds);
  one("process_resident_memory_bytes", "gauge", "Resident memory size in bytes.",
      static_cast<double>(s.resident_bytes));
  one("process_virtual_memory_bytes", "gauge", "Virtual memory size in bytes.",
      static_cast<double>(s.virtual_bytes));
  one("process_start_time_seconds", "gauge", "Start time of the process since unix epoch in seconds.",
      s.start_time_seconds);
  one("process_open_fds", "gauge", "Number of open file descriptors.", static_cast<double>(s.open_fds));
  one("process_max_fds", "gauge", "Maximum number of open file descriptors.", static_cast<double>(s.max_fds));
  one("process_threads", "gauge", "Number of OS threads in the process.", static_cast<double>(s.threads));
  return out;
}

}  // namespace fq::daemon
