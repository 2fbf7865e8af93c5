// fqd's log lines, captured in-process while the object lives (a sink on spdlog's default
// logger), for tests that count what an attack makes fqd write.
#pragma once

#include <spdlog/sinks/base_sink.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace fq::test {

class LogCapture {
 public:
  LogCapture();
  ~LogCapture();
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  /// Lines captured so far that contain `word`.
  size_t lines_with(const std::string& word);

 private:
  class Sink : public spdlog::sinks::base_sink<std::mutex> {
   public:
    size_t lines_with(const std::string& word);

   protected:
    void sink_it_(const spdlog::details::log_msg& msg) override;
    void flush_() override {}

   private:
    std::vector<std::string> lines_;
  };
  std::shared_ptr<Sink> sink_;
};

}  // namespace fq::test
