// SPDX-License-Identifier: Apache-2.0
// LoadQuantizeInput: a valid file and flags give the model, the resolved options and, for a
// server, the message (a local solve gets none); a bad file exits with 3 and bad flags with 2,
// each with the problem on stderr, whichever way the mesh goes. And MakeQuantizeRequest moves the
// mesh into a request on the mesh's arena instead of copying it.
#include "client/quantize_input.h"

#include <string>

#include "client/exit_codes.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;

v1::QuantizationOptions Factor(double s) {
  v1::QuantizationOptions options;
  options.mutable_scaling()->set_factor(s);
  return options;
}

TEST(QuantizeInputTest, AValidFileAndFlagsGiveTheResolvedInput) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
  v1::QuantizationOptions flags = Factor(3);
  flags.set_method(v1::METHOD_EXACT);
  for (const MeshUse use : {MeshUse::kSendToServer, MeshUse::kSolveHere}) {
    QuantizeInputOrExit loaded = LoadQuantizeInput(path, flags, use);
    ASSERT_TRUE(loaded.input.has_value());
    EXPECT_EQ(loaded.exit_code, kExitOk);
    EXPECT_EQ(loaded.input->options.scaling, 3);
    EXPECT_EQ(loaded.input->options.method, QuantizationMethod::kExact);
    EXPECT_EQ(loaded.input->mesh.num_arcs(), testing::TwoBlockMesh().arcs_size());
    EXPECT_EQ(loaded.input->proto.get().arcs_size(),
              use == MeshUse::kSendToServer ? testing::TwoBlockMesh().arcs_size() : 0);
  }
}

TEST(QuantizeInputTest, ABadFileExitsWithInvalidInput) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("bad.json", "not json");
  const std::string binary = folder.Write("bad.pb", "\xff\xff\xff garbage");
  for (const MeshUse use : {MeshUse::kSendToServer, MeshUse::kSolveHere}) {
    ::testing::internal::CaptureStderr();
    QuantizeInputOrExit loaded = LoadQuantizeInput(path, Factor(1), use);
    EXPECT_FALSE(loaded.input.has_value());
    EXPECT_EQ(loaded.exit_code, kExitInvalidInput);
    EXPECT_THAT(::testing::internal::GetCapturedStderr(),
                HasSubstr("ispq: " + path + ": not a T-mesh JSON document"));
    ::testing::internal::CaptureStderr();
    loaded = LoadQuantizeInput(binary, Factor(1), use);
    EXPECT_EQ(loaded.exit_code, kExitInvalidInput);
    EXPECT_THAT(::testing::internal::GetCapturedStderr(),
                HasSubstr("ispq: " + binary + ": the bytes are not a binary T-mesh"));
  }
}

// Flags are checked against the mesh before any work: a bad scaling is a usage error.
TEST(QuantizeInputTest, BadFlagsExitWithUsage) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
  v1::QuantizationOptions no_scaling;
  ::testing::internal::CaptureStderr();
  QuantizeInputOrExit loaded = LoadQuantizeInput(path, no_scaling, MeshUse::kSolveHere);
  EXPECT_THAT(::testing::internal::GetCapturedStderr(), HasSubstr("ispq: "));
  EXPECT_FALSE(loaded.input.has_value());
  EXPECT_EQ(loaded.exit_code, kExitUsage);

  v1::QuantizationOptions zero_time = Factor(1);
  zero_time.mutable_time_limit();
  ::testing::internal::CaptureStderr();
  loaded = LoadQuantizeInput(path, zero_time, MeshUse::kSendToServer);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "ispq: time limit 0s is not positive\n");
  EXPECT_EQ(loaded.exit_code, kExitUsage);
}

TEST(QuantizeInputTest, TheRequestTakesTheMeshWithoutACopy) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
  const v1::QuantizationOptions flags = Factor(2);
  QuantizeInputOrExit loaded = LoadQuantizeInput(path, flags, MeshUse::kSendToServer);
  ASSERT_TRUE(loaded.input.has_value());
  const v1::Arc* first_arc = &loaded.input->proto.get().arcs(0);
  const v1::QuantizeRequest& request = MakeQuantizeRequest(*loaded.input, flags);
  EXPECT_EQ(request.mesh().SerializeAsString(), testing::TwoBlockMesh().SerializeAsString());
  EXPECT_EQ(&request.mesh().arcs(0), first_arc);  // moved, not copied
  EXPECT_EQ(request.options().SerializeAsString(), flags.SerializeAsString());
  EXPECT_EQ(request.GetArena(), loaded.input->proto.get().GetArena());
  // The validated model stays usable.
  EXPECT_EQ(loaded.input->mesh.num_arcs(), testing::TwoBlockMesh().arcs_size());
}

}  // namespace
}  // namespace ispq::cli
