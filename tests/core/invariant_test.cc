// SPDX-License-Identifier: Apache-2.0
#include "core/invariant.h"

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(InvariantDeathTest, ReleaseInvariantAbortsNamingTheCondition) {
  const int arcs = 3;
  EXPECT_DEATH(ISPQ_RELEASE_INVARIANT(arcs == 4, "one length per arc"),
               "invariant failed: arcs == 4 \\(one length per arc\\)");
  ISPQ_RELEASE_INVARIANT(arcs == 3, "holds");
}

// Checked builds (debug and sanitizer presets) abort; release builds never evaluate the
// condition, so a check may cost what it needs to.
TEST(InvariantDeathTest, InvariantIsCheckedExactlyInCheckedBuilds) {
  int evaluations = 0;
  auto broken = [&evaluations] {
    ++evaluations;
    return false;
  };
  if (kCheckInvariants) {
    EXPECT_DEATH(ISPQ_INVARIANT(broken(), "a broken invariant"), "a broken invariant");
  } else {
    ISPQ_INVARIANT(broken(), "a broken invariant");
    EXPECT_EQ(evaluations, 0);
  }
}

}  // namespace
}  // namespace ispq
