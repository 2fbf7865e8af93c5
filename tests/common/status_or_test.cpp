// StatusOr and the FQ_RETURN_IF_ERROR / FQ_ASSIGN_OR_RETURN macros.
#include "common/status_or.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "common/status.h"

namespace fq {
namespace {

StatusOr<int> parse_positive(int v) {
  if (v <= 0) return invalid_argument("not positive: " + std::to_string(v));
  return v;
}

// Counts evaluations so the tests can see each macro evaluates its expression once.
int g_calls = 0;
Status counted(Status s) {
  ++g_calls;
  return s;
}

Status both_positive(int a, int b, int& sum) {
  FQ_ASSIGN_OR_RETURN(const int x, parse_positive(a));
  FQ_ASSIGN_OR_RETURN(const int y, parse_positive(b));
  sum = x + y;
  return {};
}

StatusOr<std::string> first_error_wins(Status a, Status b) {
  FQ_RETURN_IF_ERROR(counted(std::move(a)));
  FQ_RETURN_IF_ERROR(counted(std::move(b)));
  return std::string("both ok");
}

struct Base {
  virtual ~Base() = default;
  virtual int id() const { return 0; }
};
struct Derived : Base {
  int id() const override { return 7; }
};

StatusOr<std::unique_ptr<Base>> make(bool fail) {
  if (fail) return Status{StatusCode::kUnavailable, "no such thing"};
  return std::make_unique<Derived>();
}

TEST(CommonStatusOr, HoldsValueOrError) {
  const StatusOr<int> good = parse_positive(3);
  ASSERT_TRUE(good.ok());
  EXPECT_TRUE(good.status().ok());
  EXPECT_EQ(good.value(), 3);
  EXPECT_EQ(*good, 3);

  const StatusOr<int> bad = parse_positive(-2);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad.status().message(), "not positive: -2");
}

TEST(CommonStatusOr, OkStatusWithoutValueIsAnInternalError) {
  const StatusOr<int> s = Status{};
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kInternal);
}

TEST(CommonStatusOr, MoveOnlyValueConvertsToBase) {
  StatusOr<std::unique_ptr<Base>> made = make(false);
  ASSERT_TRUE(made.ok());
  std::unique_ptr<Base> b = std::move(made).value();
  ASSERT_TRUE(b);
  EXPECT_EQ(b->id(), 7);
  EXPECT_EQ(make(true).status().code(), StatusCode::kUnavailable);
}

TEST(CommonStatusMacros, AssignOrReturnAssignsOrPropagates) {
  int sum = -1;
  EXPECT_TRUE(both_positive(2, 5, sum).ok());
  EXPECT_EQ(sum, 7);
  sum = -1;
  const Status s = both_positive(2, 0, sum);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "not positive: 0");
  EXPECT_EQ(sum, -1);  // the function returned before the assignment
}

TEST(CommonStatusMacros, ReturnIfErrorStopsAtTheFirstErrorAndEvaluatesOnce) {
  g_calls = 0;
  StatusOr<std::string> r = first_error_wins({}, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, "both ok");
  EXPECT_EQ(g_calls, 2);

  g_calls = 0;
  r = first_error_wins(io_error("cannot open 'x'"), invalid_input("never seen"));
  EXPECT_EQ(r.status().code(), StatusCode::kIoError);
  EXPECT_EQ(r.status().message(), "cannot open 'x'");
  EXPECT_EQ(g_calls, 1);
}

TEST(CommonStatus, EveryCodeHasAName) {
  EXPECT_STREQ(status_code_name(StatusCode::kOk), "ok");
  EXPECT_STREQ(status_code_name(StatusCode::kInvalidArgument), "invalid argument");
  EXPECT_STREQ(status_code_name(StatusCode::kInvalidInput), "invalid input");
  EXPECT_STREQ(status_code_name(StatusCode::kUnavailable), "unavailable");
  EXPECT_STREQ(status_code_name(StatusCode::kInternal), "internal error");
  EXPECT_STREQ(status_code_name(StatusCode::kIoError), "i/o error");
}

}  // namespace
}  // namespace fq
