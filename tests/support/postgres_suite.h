// SPDX-License-Identifier: Apache-2.0
// The fixture of a test suite that needs PostgreSQL: one instance (tests/support/
// postgres_instance.h) started for the whole suite, since a start costs seconds, and stopped after
// it; each test creates the databases it needs (postgres_->CreateDatabase), numbered with
// next_database_ so that tests of one suite never share one.
#ifndef ISPQ_TESTS_SUPPORT_POSTGRES_SUITE_H_
#define ISPQ_TESTS_SUPPORT_POSTGRES_SUITE_H_

#include <memory>

#include "absl/status/statusor.h"
#include "gtest/gtest.h"
#include "tests/support/postgres_instance.h"

namespace ispq::testing {

class PostgresSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    absl::StatusOr<std::unique_ptr<PostgresInstance>> started = PostgresInstance::Start();
    ASSERT_TRUE(started.ok()) << started.status();
    postgres_ = started->release();
  }
  static void TearDownTestSuite() {
    delete postgres_;
    postgres_ = nullptr;
  }

  // Suites run one after the other: each derived suite has the instance to itself.
  inline static PostgresInstance* postgres_ = nullptr;
  inline static int next_database_ = 0;
};

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_POSTGRES_SUITE_H_
