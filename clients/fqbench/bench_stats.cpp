#include "clients/fqbench/bench_stats.h"

#include <chrono>
#include <ctime>

#include "common/sample_stats.h"

namespace fq::bench {

Spread spread_of(const std::vector<double>& v) {
  return {median(v), percentile(v, 0.1), percentile(v, 0.9), static_cast<int>(v.size())};
}

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

void time_step(const std::function<bool()>& step, bool& ok, std::vector<double>& wall,
               std::vector<double>& cpu) {
  const double c0 = cpu_ms();
  const auto t0 = std::chrono::steady_clock::now();
  ok = step() && ok;
  wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  cpu.push_back(cpu_ms() - c0);
}

bool is_host_or_transfer(const std::string& pass) {
  return pass == "upload" || pass == "download" || pass == "normalize" || pass == "prepare" ||
         pass == "finish" || pass == "weld";
}

void PassSamples::push(const std::string& name, double ms) {
  if (!samples_.count(name)) names_.push_back(name);
  samples_[name].push_back(ms);
}

void PassSamples::add(const FrameResult& r) {
  double device = 0.0;
  for (const PassTiming& t : r.timings) {
    push(t.name, t.ms);
    if (!is_host_or_transfer(t.name)) device += t.ms;
  }
  push("device", device);
  push("frame", r.total_ms());
}

Spread PassSamples::spread(const std::string& name) const {
  const auto it = samples_.find(name);
  return it == samples_.end() ? Spread{} : spread_of(it->second);
}

}  // namespace fq::bench
