#include "clients/fqbench/bench_stats.h"

#include "common/sample_stats.h"

namespace fq::bench {

Spread spread_of(const std::vector<double>& v) {
  return {median(v), percentile(v, 0.1), percentile(v, 0.9), static_cast<int>(v.size())};
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
