#include "tests/daemon/log_capture.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace fq::test {

void LogCapture::Sink::sink_it_(const spdlog::details::log_msg& msg) {
  lines_.emplace_back(msg.payload.data(), msg.payload.size());  // under the sink's mutex
}

size_t LogCapture::Sink::lines_with(const std::string& word) {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<size_t>(std::count_if(
      lines_.begin(), lines_.end(), [&](const std::string& l) { return l.find(word) != std::string::npos; }));
}

LogCapture::LogCapture() : sink_(std::make_shared<Sink>()) {
  spdlog::default_logger()->sinks().push_back(sink_);
}

LogCapture::~LogCapture() {
  auto& sinks = spdlog::default_logger()->sinks();
  sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
}

size_t LogCapture::lines_with(const std::string& word) { return sink_->lines_with(word); }

}  // namespace fq::test
