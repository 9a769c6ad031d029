// SPDX-License-Identifier: Apache-2.0
#include "server/model/resource_names.h"

#include <set>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(ResourceNamesTest, IssuesDistinctHexIds) {
  std::set<std::string> ids;
  for (int i = 0; i < 1000; ++i) {
    const std::string id = NewResourceId();
    EXPECT_EQ(id.size(), 16u);
    EXPECT_EQ(id.find_first_not_of("0123456789abcdef"), std::string::npos);
    ids.insert(id);
  }
  EXPECT_EQ(ids.size(), 1000u);
}

TEST(ResourceNamesTest, ParsesWellFormedNamesOnly) {
  EXPECT_EQ(*ParseResourceName(kJobCollection, "jobs/0123abcd"), "0123abcd");
  EXPECT_EQ(ResourceName(kMeshCollection, "x1"), "meshes/x1");
  const std::vector<std::string> bad_names = {"",
                                              "jobs/",
                                              "jobs",
                                              "meshes/abc",
                                              "jobs/ABC",
                                              "jobs/a/b",
                                              "jobs/../x",
                                              std::string("jobs/a\0b", 8),
                                              absl::StrCat("jobs/", std::string(64, 'a'))};
  for (const std::string& bad : bad_names) {
    EXPECT_EQ(ParseResourceName(kJobCollection, bad).status().code(),
              absl::StatusCode::kInvalidArgument)
        << bad;
  }
  EXPECT_TRUE(ParseResourceName(kJobCollection, absl::StrCat("jobs/", std::string(63, 'a'))).ok());
}

}  // namespace
}  // namespace ispq::server
