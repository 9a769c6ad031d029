// SPDX-License-Identifier: Apache-2.0
// CheckHealth through its generic stub against gRPC's own health service on an in-process
// server: the whole server and a named service report their status, an unknown service is
// NOT_FOUND, and nothing answering is UNAVAILABLE.
#include "client/health_check.h"

#include <memory>
#include <string>

#include "grpcpp/create_channel.h"
#include "grpcpp/health_check_service_interface.h"
#include "grpcpp/server.h"
#include "grpcpp/server_builder.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"

namespace ispq::client {
namespace {

class HealthCheckTest : public ::testing::Test {
 protected:
  HealthCheckTest() {
    grpc::EnableDefaultHealthCheckService(true);
    grpc::ServerBuilder builder;
    // A synchronous server needs one service of its own; the health service comes with it.
    builder.RegisterService(&quantizer_);
    server_ = builder.BuildAndStart();
    channel_ = server_->InProcessChannel(grpc::ChannelArguments());
  }
  ~HealthCheckTest() override { server_->Shutdown(); }

  v1::Quantizer::Service quantizer_;  // every method UNIMPLEMENTED
  std::unique_ptr<grpc::Server> server_;
  std::shared_ptr<grpc::Channel> channel_;
};

TEST_F(HealthCheckTest, TheServerAndItsServicesReportTheirStatus) {
  const absl::StatusOr<ServingStatus> server = CheckHealth(channel_, "", absl::Seconds(30));
  ASSERT_TRUE(server.ok()) << server.status();
  EXPECT_EQ(*server, ServingStatus::kServing);

  grpc::HealthCheckServiceInterface* health = server_->GetHealthCheckService();
  ASSERT_NE(health, nullptr);
  health->SetServingStatus("ispq.v1.Quantizer", false);
  EXPECT_EQ(*CheckHealth(channel_, "ispq.v1.Quantizer", absl::Seconds(30)),
            ServingStatus::kNotServing);
  health->SetServingStatus("ispq.v1.Quantizer", true);
  EXPECT_EQ(*CheckHealth(channel_, "ispq.v1.Quantizer", absl::Seconds(30)),
            ServingStatus::kServing);
}

TEST_F(HealthCheckTest, AnUnknownServiceIsNotFound) {
  const absl::StatusOr<ServingStatus> status =
      CheckHealth(channel_, "no.such.Service", absl::Seconds(30));
  EXPECT_EQ(status.status().code(), absl::StatusCode::kNotFound);
}

TEST(HealthCheckNoServerTest, NothingAnsweringIsUnavailable) {
  // Port 1 on loopback: nothing listens there, the connection is refused at once.
  const std::shared_ptr<grpc::Channel> channel =
      grpc::CreateChannel("127.0.0.1:1", grpc::InsecureChannelCredentials());
  const absl::StatusOr<ServingStatus> status = CheckHealth(channel, "", absl::Seconds(30));
  EXPECT_EQ(status.status().code(), absl::StatusCode::kUnavailable);
}

TEST(HealthCheckNoServerTest, StatusNamesAreTheProtocolsNames) {
  EXPECT_STREQ(ServingStatusName(ServingStatus::kUnknown), "UNKNOWN");
  EXPECT_STREQ(ServingStatusName(ServingStatus::kServing), "SERVING");
  EXPECT_STREQ(ServingStatusName(ServingStatus::kNotServing), "NOT_SERVING");
  EXPECT_STREQ(ServingStatusName(ServingStatus::kServiceUnknown), "SERVICE_UNKNOWN");
}

}  // namespace
}  // namespace ispq::client
