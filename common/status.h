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
  kIoError,          ///< a file that cannot be found, opened, read or written
  kCancelled,        ///< work stopped by its time limit or a shutdown (core/cancel_token.h)
};

/// [[nodiscard]]: a dropped Status is a dropped error, so the compiler names every call that
/// ignores one; `(void)` marks the few that mean to (a fuzzer that only looks for crashes).
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status invalid_argument(std::string m) { return {StatusCode::kInvalidArgument, std::move(m)}; }
inline Status invalid_input(std::string m) { return {StatusCode::kInvalidInput, std::move(m)}; }
inline Status io_error(std::string m) { return {StatusCode::kIoError, std::move(m)}; }

/// "invalid argument", "i/o error", ... for messages.
const char* status_code_name(StatusCode code);

}  // namespace fq

/// Evaluates `expression` (a Status) once and returns it from the enclosing function when it
/// is an error (Draco's DRACO_RETURN_IF_ERROR). The enclosing function returns Status or StatusOr.
#define FQ_RETURN_IF_ERROR(expression)                   \
  do {                                                   \
    ::fq::Status fq_status_macro_ = (expression);        \
    if (!fq_status_macro_.ok()) return fq_status_macro_; \
  } while (false)
