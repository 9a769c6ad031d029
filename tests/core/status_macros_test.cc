// SPDX-License-Identifier: Apache-2.0
#include "core/status_macros.h"

#include <memory>
#include <string>

#include "gtest/gtest.h"

namespace ispq {
namespace {

absl::Status FailIf(bool fail, int* calls) {
  ++*calls;
  return fail ? absl::InvalidArgumentError("failed") : absl::OkStatus();
}

absl::Status TwoSteps(bool fail_first, int* calls) {
  ISPQ_RETURN_IF_ERROR(FailIf(fail_first, calls));
  ISPQ_RETURN_IF_ERROR(FailIf(false, calls));
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<int>> Make(bool fail) {
  if (fail) return absl::NotFoundError("none");
  return std::make_unique<int>(7);
}

absl::StatusOr<int> Unwrap(bool fail) {
  ISPQ_ASSIGN_OR_RETURN(std::unique_ptr<int> value, Make(fail));         // move-only works
  ISPQ_ASSIGN_OR_RETURN(const std::unique_ptr<int> again, Make(false));  // twice in one scope
  return *value + *again;
}

TEST(StatusMacrosTest, ReturnIfErrorStopsAtTheFirstErrorAndEvaluatesOnce) {
  int calls = 0;
  EXPECT_EQ(TwoSteps(true, &calls).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(calls, 1);
  calls = 0;
  EXPECT_TRUE(TwoSteps(false, &calls).ok());
  EXPECT_EQ(calls, 2);
}

TEST(StatusMacrosTest, AssignOrReturnDeclaresTheValueOrReturnsTheError) {
  EXPECT_EQ(*Unwrap(false), 14);
  EXPECT_EQ(Unwrap(true).status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace ispq
