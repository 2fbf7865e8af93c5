// A value or the Status that says why there is none (Draco's core/status_or.h), for
// functions that would otherwise return a Status and fill an out-parameter.
#pragma once

#include <optional>
#include <type_traits>
#include <utility>

#include "common/status.h"

namespace fq {

template <typename T>
class [[nodiscard]] StatusOr {
 public:
  /// An error. An ok status carries no value, so it becomes an internal error rather than
  /// a StatusOr whose value() would be missing.
  StatusOr(Status status) : status_(std::move(status)) {  // NOLINT(google-explicit-constructor)
    if (status_.ok()) status_ = {StatusCode::kInternal, "StatusOr built from an ok status without a value"};
  }
  StatusOr(T value) : value_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  /// Converts a value of another type (a unique_ptr<Derived> into a unique_ptr<Base>).
  template <typename U, typename = std::enable_if_t<std::is_convertible_v<U&&, T> &&
                                                    !std::is_same_v<std::decay_t<U>, T> &&
                                                    !std::is_convertible_v<U&&, Status>>>
  StatusOr(U&& value) : value_(T(std::forward<U>(value))) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }

  /// The value; only when ok().
  const T& value() const& { return *value_; }
  T& value() & { return *value_; }
  T&& value() && { return std::move(*value_); }
  const T& operator*() const& { return *value_; }
  T& operator*() & { return *value_; }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace fq

#define FQ_STATUS_MACROS_CONCAT_INNER(a, b) a##b
#define FQ_STATUS_MACROS_CONCAT(a, b) FQ_STATUS_MACROS_CONCAT_INNER(a, b)

/// `FQ_ASSIGN_OR_RETURN(auto mesh, read(path));` evaluates the StatusOr expression once,
/// returns its status from the enclosing function on error, and otherwise moves its value into
/// `lhs` (a declaration or an existing variable). Draco's DRACO_ASSIGN_OR_RETURN.
#define FQ_ASSIGN_OR_RETURN(lhs, expression) \
  FQ_ASSIGN_OR_RETURN_IMPL(FQ_STATUS_MACROS_CONCAT(fq_status_or_, __LINE__), lhs, expression)

// NOLINTBEGIN(bugprone-macro-parentheses): lhs is a declaration and tmp a name; neither
// can stand in parentheses.
#define FQ_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expression) \
  auto tmp = (expression);                             \
  if (!tmp.ok()) return tmp.status();                  \
  lhs = std::move(tmp).value()
// NOLINTEND(bugprone-macro-parentheses)
