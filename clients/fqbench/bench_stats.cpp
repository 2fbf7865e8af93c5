#include "clients/fqbench/bench_stats.h"

#include <algorithm>
#include <cmath>

namespace fq::bench {

Spread spread_of(std::vector<double> v) {
  Spread s;
  s.count = static_cast<int>(v.size());
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    return v[std::min(v.size() - 1, size_t(std::floor(q * double(v.size() - 1) + 0.5)))];
  };
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  s.p10 = at(0.1);
  s.p90 = at(0.9);
  return s;
}

bool is_host_or_transfer(const std::string& pass) {
  return pass == "upload" || pass == "download" || pass == "normalize" || pass == "prepare" ||
         pass == "finish";
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
