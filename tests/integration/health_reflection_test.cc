// SPDX-License-Identifier: Apache-2.0
// Standard gRPC health checking and server reflection, which orchestrators (Kubernetes gRPC
// probes) and grpcurl rely on. Debian ships no generated stubs for either protocol, so these
// tests speak them through generic stubs: the health check through the client library
// (client/health_check.h), reflection with hand-encoded messages read back as unknown fields.
#include <memory>
#include <string>
#include <vector>

#include "client/health_check.h"
#include "gmock/gmock.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/descriptor.pb.h"
#include "google/protobuf/unknown_field_set.h"
#include "grpcpp/client_context.h"
#include "grpcpp/completion_queue.h"
#include "grpcpp/generic/generic_stub.h"
#include "grpcpp/support/byte_buffer.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"

namespace ispq::testing {
namespace {

using ::testing::Contains;
using ::testing::IsSupersetOf;

constexpr char kReflectionMethod[] =
    "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo";
// Field numbers of grpc.reflection.v1alpha (reflection.proto).
constexpr int kRequestFileContainingSymbol = 4;
constexpr int kRequestListServices = 7;
constexpr int kResponseFileDescriptors = 4;
constexpr int kResponseListServices = 6;

std::string LengthDelimitedField(int field, const std::string& value) {
  std::string encoded(1, static_cast<char>(field << 3 | 2));
  for (size_t n = value.size(); true; n >>= 7) {
    encoded += static_cast<char>(n >= 0x80 ? (n & 0x7f) | 0x80 : n);
    if (n < 0x80) break;
  }
  return encoded + value;
}

// The length-delimited values of `field` in a serialized message.
std::vector<std::string> FieldValues(const std::string& message, int field) {
  google::protobuf::UnknownFieldSet fields;
  EXPECT_TRUE(fields.ParseFromString(message));
  std::vector<std::string> values;
  for (int i = 0; i < fields.field_count(); ++i) {
    const google::protobuf::UnknownField& f = fields.field(i);
    if (f.number() == field && f.type() == google::protobuf::UnknownField::TYPE_LENGTH_DELIMITED) {
      values.push_back(f.length_delimited());
    }
  }
  return values;
}

std::string BufferToString(const grpc::ByteBuffer& buffer) {
  std::vector<grpc::Slice> slices;
  EXPECT_TRUE(buffer.Dump(&slices).ok());
  std::string bytes;
  for (const grpc::Slice& slice : slices) {
    bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  }
  return bytes;
}

// One request and its response on the reflection stream.
std::string ReflectionExchange(const std::shared_ptr<grpc::Channel>& channel,
                               const std::string& request) {
  grpc::GenericStub stub(channel);
  grpc::CompletionQueue queue;
  grpc::ClientContext context;
  context.set_deadline(absl::ToChronoTime(absl::Now() + absl::Seconds(30)));
  const auto step = [&queue]() {
    void* tag = nullptr;
    bool ok = false;
    EXPECT_TRUE(queue.Next(&tag, &ok));
    return ok;
  };
  std::unique_ptr<grpc::GenericClientAsyncReaderWriter> call =
      stub.PrepareCall(&context, kReflectionMethod, &queue);
  call->StartCall(nullptr);
  EXPECT_TRUE(step());
  grpc::Slice slice(request);
  call->Write(grpc::ByteBuffer(&slice, 1), nullptr);
  EXPECT_TRUE(step());
  grpc::ByteBuffer response;
  call->Read(&response, nullptr);
  const bool read = step();
  call->WritesDone(nullptr);
  step();
  grpc::Status status;
  call->Finish(&status, nullptr);
  step();
  EXPECT_TRUE(read);
  EXPECT_TRUE(status.ok()) << status.error_message();
  queue.Shutdown();
  void* tag;
  bool ok;
  while (queue.Next(&tag, &ok)) {
  }
  return read ? BufferToString(response) : "";
}

TEST(HealthTest, ServerAndServiceAreServing) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  const client::QuantizerClient client = ClientOf(*server);
  for (const std::string service : {"", "ispq.v1.Quantizer"}) {
    const absl::StatusOr<client::ServingStatus> status =
        client::CheckHealth(client.channel(), service, absl::Seconds(30));
    ASSERT_TRUE(status.ok()) << status.status();
    EXPECT_EQ(*status, client::ServingStatus::kServing) << "service '" << service << "'";
  }
  const absl::StatusOr<client::ServingStatus> unknown =
      client::CheckHealth(client.channel(), "no.such.Service", absl::Seconds(30));
  EXPECT_EQ(unknown.status().code(), absl::StatusCode::kNotFound);
}

TEST(ReflectionTest, ListsTheServices) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  const client::QuantizerClient client = ClientOf(*server);
  const std::string response =
      ReflectionExchange(client.channel(), LengthDelimitedField(kRequestListServices, "*"));
  const std::vector<std::string> lists = FieldValues(response, kResponseListServices);
  ASSERT_EQ(lists.size(), 1u);
  std::vector<std::string> names;
  for (const std::string& service : FieldValues(lists[0], 1)) {
    const std::vector<std::string> name = FieldValues(service, 1);
    ASSERT_EQ(name.size(), 1u);
    names.push_back(name[0]);
  }
  EXPECT_THAT(names, IsSupersetOf({"ispq.v1.Quantizer", "grpc.health.v1.Health",
                                   "grpc.reflection.v1alpha.ServerReflection"}));
}

TEST(ReflectionTest, DescribesTheQuantizerWithItsDependencies) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  const client::QuantizerClient client = ClientOf(*server);
  const std::string response = ReflectionExchange(
      client.channel(), LengthDelimitedField(kRequestFileContainingSymbol, "ispq.v1.Quantizer"));
  const std::vector<std::string> files = FieldValues(response, kResponseFileDescriptors);
  ASSERT_EQ(files.size(), 1u);
  std::vector<std::string> file_names;
  bool quantizer_found = false;
  for (const std::string& bytes : FieldValues(files[0], 1)) {
    google::protobuf::FileDescriptorProto file;
    ASSERT_TRUE(file.ParseFromString(bytes));
    file_names.push_back(file.name());
    for (const google::protobuf::ServiceDescriptorProto& service : file.service()) {
      // Every method the schema this test was built with has, UploadMesh included.
      const int methods =
          v1::QuantizeRequest::descriptor()->file()->FindServiceByName("Quantizer")->method_count();
      if (service.name() == "Quantizer") quantizer_found = service.method_size() == methods;
    }
  }
  EXPECT_TRUE(quantizer_found);
  EXPECT_THAT(file_names, Contains("ispq/v1/service.proto"));
  EXPECT_THAT(file_names, IsSupersetOf({"ispq/v1/tmesh.proto", "ispq/v1/quantization.proto",
                                        "google/protobuf/duration.proto"}));
}

}  // namespace
}  // namespace ispq::testing
