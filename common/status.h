// Expected failures of a frame are values, not exceptions (as Draco's core/status.h).
#pragma once

#include <string>
#include <utility>

namespace fq {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,  ///< bad parameters
  kInvalidInput,     ///< bad mesh (indices out of range, NaN coordinates, no triangles...)
  kUnavailable,      ///< a requested engine or device is not present
  kInternal,         ///< a fault caught at the frame boundary (e.g. a CUDA error)
};

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status ok_status() { return {}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status invalid_argument(std::string m) { return {StatusCode::kInvalidArgument, std::move(m)}; }
inline Status invalid_input(std::string m) { return {StatusCode::kInvalidInput, std::move(m)}; }

const char* status_code_name(StatusCode code);

}  // namespace fq
