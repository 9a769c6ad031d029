// SPDX-License-Identifier: Apache-2.0
// A file through which the child of a death test tells its parent what it started (pids,
// directories) before it dies, so that the parent can check that those died with it.
//
// gtest's "threadsafe" death tests run the test again in a fresh process, started with the
// parent's environment; the parent chooses the path and puts it in the environment, so parent
// and child name the same file without sharing memory.
#ifndef ISPQ_TESTS_INTEGRATION_DEATH_TEST_RECORD_H_
#define ISPQ_TESTS_INTEGRATION_DEATH_TEST_RECORD_H_

#include <stdlib.h>
#include <unistd.h>

#include <string>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"

namespace ispq::testing {

inline std::string DeathTestRecordPath() {
  constexpr char kVariable[] = "ISPQ_DEATH_TEST_RECORD";
  if (const char* inherited = getenv(kVariable)) return inherited;
  const std::string path = absl::StrCat(::testing::TempDir(), "ispq_death_test_record_", getpid());
  setenv(kVariable, path.c_str(), 1);
  return path;
}

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_DEATH_TEST_RECORD_H_
