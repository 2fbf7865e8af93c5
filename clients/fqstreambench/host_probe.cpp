#include "clients/fqstreambench/host_probe.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include "common/sample_stats.h"

namespace fq::bench {

namespace {

std::optional<CpuTicks> read_cpu_ticks() {
  std::ifstream in("/proc/stat");
  std::string line;
  if (!std::getline(in, line)) return std::nullopt;
  return parse_cpu_line(line);
}

}  // namespace

std::optional<CpuTicks> parse_cpu_line(const std::string& line) {
  std::istringstream in(line);
  std::string name;
  if (!(in >> name) || name != "cpu") return std::nullopt;
  // user nice system idle iowait irq softirq steal: guest time is counted in user already.
  uint64_t v[8];
  for (uint64_t& x : v)
    if (!(in >> x)) return std::nullopt;
  CpuTicks t;
  for (uint64_t x : v) t.total += x;
  t.steal = v[7];
  return t;
}

HostProbe::~HostProbe() {
  if (thread_.joinable()) (void)stop();
}

void HostProbe::start() {
  late_ms_.clear();
  late_ms_.reserve(1 << 16);
  stop_ = false;
  ticks0_ = read_cpu_ticks();
  thread_ = std::thread([this] {
    using clock = std::chrono::steady_clock;
    constexpr auto kNap = std::chrono::milliseconds(1);
    while (!stop_.load(std::memory_order_relaxed)) {
      const auto t0 = clock::now();
      std::this_thread::sleep_for(kNap);
      late_ms_.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0 - kNap).count());
    }
  });
}

HostQuiet HostProbe::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  HostQuiet q;
  q.wakeups = late_ms_.size();
  if (!late_ms_.empty()) {
    q.late_p50_ms = median(late_ms_);
    q.late_p99_ms = percentile(late_ms_, 0.99);
    q.late_max_ms = *std::max_element(late_ms_.begin(), late_ms_.end());
    q.late_over_5ms = static_cast<uint64_t>(
        std::count_if(late_ms_.begin(), late_ms_.end(), [](double x) { return x > 5.0; }));
  }
  const std::optional<CpuTicks> t1 = read_cpu_ticks();
  if (ticks0_ && t1 && t1->total > ticks0_->total && t1->steal >= ticks0_->steal)
    q.steal_share = double(t1->steal - ticks0_->steal) / double(t1->total - ticks0_->total);
  return q;
}

}  // namespace fq::bench
