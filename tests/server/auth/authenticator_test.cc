// SPDX-License-Identifier: Apache-2.0
// The principal a call is made by (server/auth/authenticator.h), through the path both
// transports share: a bearer token's principal, admins, the anonymous principal without tokens,
// and no way around client certificates over plaintext HTTP; and what a call over mutual TLS
// presents (its certificate's subject). Reading those from a gRPC call
// (server/grpc/call_principal.h) is covered by the integration tests that start real servers
// with tokens and certificates.
#include "server/auth/authenticator.h"

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

AuthenticationConfig WithTokens() {
  AuthenticationConfig config;
  config.tokens = {{"alice", "token-of-alice"}, {"bob", "token-of-bob"}};
  config.admin_principals = {"bob"};
  return config;
}

TEST(AuthenticatorTest, ABearerTokenNamesItsPrincipal) {
  const Authenticator authenticator(WithTokens());
  const absl::StatusOr<Principal> alice = authenticator.AuthenticateHttp("Bearer token-of-alice");
  ASSERT_TRUE(alice.ok()) << alice.status();
  EXPECT_EQ(alice->name, "alice");
  EXPECT_FALSE(alice->admin);
  EXPECT_TRUE(alice->CanAccess("alice"));
  EXPECT_FALSE(alice->CanAccess("bob"));

  const absl::StatusOr<Principal> bob = authenticator.AuthenticateHttp("Bearer token-of-bob");
  ASSERT_TRUE(bob.ok()) << bob.status();
  EXPECT_EQ(bob->name, "bob");
  EXPECT_TRUE(bob->admin);
  EXPECT_TRUE(bob->CanAccess("alice"));
}

TEST(AuthenticatorTest, AWrongMissingOrMalformedTokenIsUnauthenticated) {
  const Authenticator authenticator(WithTokens());
  for (const char* header :
       {"", "Bearer", "Bearer ", "Bearer token-of-alicE", "bearer token-of-alice", "token-of-alice",
        "Bearer token-of-alice ", "Basic dG9rZW4="}) {
    const absl::StatusOr<Principal> principal = authenticator.AuthenticateHttp(header);
    EXPECT_TRUE(absl::IsUnauthenticated(principal.status())) << "'" << header << "'";
  }
}

TEST(AuthenticatorTest, WithoutTokensOrCertificatesEveryCallerIsAnonymous) {
  AuthenticationConfig config;
  config.admin_principals = {""};  // an open server may make the anonymous principal admin
  const Authenticator authenticator(config);
  for (const char* header : {"", "Bearer anything"}) {
    const absl::StatusOr<Principal> principal = authenticator.AuthenticateHttp(header);
    ASSERT_TRUE(principal.ok()) << principal.status();
    EXPECT_EQ(principal->name, "");
    EXPECT_TRUE(principal->admin);
  }
}

TEST(AuthenticatorTest, PlaintextHttpNeverBypassesClientCertificates) {
  AuthenticationConfig config;
  config.client_certificates = true;
  const Authenticator authenticator(config);
  const absl::StatusOr<Principal> principal = authenticator.AuthenticateHttp("");
  EXPECT_TRUE(absl::IsUnauthenticated(principal.status()));
  EXPECT_NE(principal.status().message().find("client certificate"), std::string::npos);

  // With tokens as well, the certificate only secures the connection: the token names the
  // principal, over HTTP too.
  AuthenticationConfig both = WithTokens();
  both.client_certificates = true;
  const absl::StatusOr<Principal> alice =
      Authenticator(both).AuthenticateHttp("Bearer token-of-alice");
  ASSERT_TRUE(alice.ok()) << alice.status();
  EXPECT_EQ(alice->name, "alice");
}

TEST(AuthenticatorTest, WithoutTokensAVerifiedCertificateNamesThePrincipal) {
  AuthenticationConfig config;
  config.client_certificates = true;
  config.admin_principals = {"CN=root"};
  const Authenticator authenticator(config);
  EXPECT_TRUE(authenticator.NamesByCertificate());
  const absl::StatusOr<Principal> alice =
      authenticator.Authenticate("Bearer anything", "CN=alice,O=Example");
  ASSERT_TRUE(alice.ok()) << alice.status();
  EXPECT_EQ(alice->name, "CN=alice,O=Example");
  EXPECT_FALSE(alice->admin);
  const absl::StatusOr<Principal> root = authenticator.Authenticate("", "CN=root");
  ASSERT_TRUE(root.ok()) << root.status();
  EXPECT_TRUE(root->admin);
  EXPECT_TRUE(absl::IsUnauthenticated(authenticator.Authenticate("", "").status()));

  // With tokens the token names the principal, whatever the certificate says.
  AuthenticationConfig both = WithTokens();
  both.client_certificates = true;
  const Authenticator tokens(both);
  EXPECT_FALSE(tokens.NamesByCertificate());
  const absl::StatusOr<Principal> bob = tokens.Authenticate("Bearer token-of-bob", "CN=alice");
  ASSERT_TRUE(bob.ok()) << bob.status();
  EXPECT_EQ(bob->name, "bob");
  EXPECT_TRUE(absl::IsUnauthenticated(tokens.Authenticate("", "CN=alice").status()));
}

}  // namespace
}  // namespace ispq::server
