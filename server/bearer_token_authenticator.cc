#include "server/bearer_token_authenticator.h"

#include <string_view>
#include <utility>

namespace ispq::server {
namespace {

constexpr std::string_view kBearerPrefix = "Bearer ";

// Compares in time that depends on the lengths only, so that the token cannot be guessed one
// byte at a time from response times.
bool ConstantTimeEquals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  }
  return difference == 0;
}

}  // namespace

BearerTokenAuthenticator::BearerTokenAuthenticator(std::string token) : token_(std::move(token)) {}

grpc::Status BearerTokenAuthenticator::Check(const grpc::ServerContextBase& context) const {
  if (!enabled()) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  if (it != metadata.end()) {
    const std::string_view value(it->second.data(), it->second.size());
    if (value.substr(0, kBearerPrefix.size()) == kBearerPrefix &&
        ConstantTimeEquals(value.substr(kBearerPrefix.size()), token_)) {
      return grpc::Status::OK;
    }
  }
  return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                      "missing or wrong bearer token (metadata 'authorization: Bearer <token>')");
}

}  // namespace ispq::server
