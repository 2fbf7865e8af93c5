#include "clients/common/stream_stats.h"

#include <cstdio>
#include <utility>

#include "common/sample_stats.h"

namespace fq::client {
namespace {

nlohmann::json summary(const std::vector<double>& v) {
  return {{"p50_ms", percentile(v, 0.50)},
          {"p95_ms", percentile(v, 0.95)},
          {"p99_ms", percentile(v, 0.99)},
          {"count", v.size()}};
}

// The reason of an error result whose frame fqd stopped on the engine, from the word fqd's
// error starts with (daemon/pipeline/frame_stages.cpp); nullptr for other errors (a bad frame).
const char* stopped_reason(const std::string& error) {
  constexpr std::pair<const char*, const char*> kStopped[] = {
      {"preempted:", "preempted"}, {"time_limit:", "time_limit"}, {"cancelled:", "stopping"}};
  for (const auto& [prefix, reason] : kStopped)
    if (error.starts_with(prefix)) return reason;
  return nullptr;
}

}  // namespace

uint64_t StreamStats::drops() const {
  uint64_t n = 0;
  for (const auto& [reason, count] : drops_by_reason_) n += count;
  return n;
}

void StreamStats::add(const ReceivedResult& r, bool ok) {
  const wire::ResultHeader& h = r.header;
  if (results_ == 0) first_ns_ = r.receive_ns;
  last_ns_ = r.receive_ns;
  ++results_;
  // A gap in a stream's sequence numbers: frames without a result here (the header comment
  // says why their reason is not known here).
  auto [it, fresh] = next_seq_.try_emplace(h.stream_id(), h.sequence());
  if (!fresh && h.sequence() > it->second) drops_by_reason_["gap"] += h.sequence() - it->second;
  it->second = h.sequence() + 1;
  if (!ok) ++bad_;
  if (h.status() == wire::ERROR) {
    ++errors_;
    if (const char* reason = stopped_reason(h.error())) ++drops_by_reason_[reason];
    return;
  }
  if (h.status() == wire::LATE) ++late_;
  latency_.push_back(h.latency_ms());
  if (h.send_time_ns() > 0) send_to_receive_.push_back(send_to_receive_ms(r));
  for (const wire::StageTiming& t : h.timings()) stages_[t.name()].push_back(t.ms());
  last_noise_ = h.noise_estimate();
}

double StreamStats::fps() const {
  if (results_ < 2 || last_ns_ <= first_ns_) return 0.0;
  return static_cast<double>(results_ - 1) / (static_cast<double>(last_ns_ - first_ns_) * 1e-9);
}

std::string StreamStats::status_line() const {
  std::string reasons;  // "drops 12 (gap 10, preempted 2)"
  for (const auto& [reason, count] : drops_by_reason_)
    reasons += (reasons.empty() ? " (" : ", ") + reason + " " + std::to_string(count);
  if (!reasons.empty()) reasons += ")";
  char line[384];
  const int used = std::snprintf(
      line, sizeof line,
      "%llu results  %.1f fps  latency p50 %.1f p99 %.1f ms  send->recv p50 %.1f p99 %.1f ms  drops %llu%s  "
      "errors %llu  late %llu  bad %llu",
      static_cast<unsigned long long>(results_), fps(), percentile(latency_, 0.5), percentile(latency_, 0.99),
      percentile(send_to_receive_, 0.5), percentile(send_to_receive_, 0.99),
      static_cast<unsigned long long>(drops()), reasons.c_str(), static_cast<unsigned long long>(errors_),
      static_cast<unsigned long long>(late_), static_cast<unsigned long long>(bad_));
  if (last_noise_ > 0.f && used > 0 && size_t(used) < sizeof line)
    std::snprintf(line + used, sizeof line - size_t(used), "  noise %.3f", last_noise_);
  return line;
}

nlohmann::json StreamStats::to_json() const {
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, v] : stages_) stages[name] = summary(v);
  return {{"results", results_},
          {"errors", errors_},
          {"bad", bad_},
          {"drops", drops()},
          {"drops_by_reason", drops_by_reason_},
          {"late", late_},
          {"fps", fps()},
          {"receive_to_publish", summary(latency_)},
          {"send_to_receive", summary(send_to_receive_)},
          {"stages", stages},
          {"noise_estimate", last_noise_}};
}

}  // namespace fq::client
