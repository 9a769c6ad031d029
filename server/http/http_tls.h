// SPDX-License-Identifier: Apache-2.0
// The certificate and private key the HTTP side serves HTTPS with (--http_tls_cert and
// --http_tls_key, by default gRPC's --tls_cert and --tls_key: server/server_config.h), read and
// checked once at start.
//
// libmicrohttpd runs TLS on GnuTLS and, given a file it cannot use, only fails to start its
// daemon. So the files are checked here first with GnuTLS itself, the same parser that will load
// them: a missing file, a certificate file without a certificate, a key file without an
// (unencrypted) key, or a key that does not belong to the certificate stop the server with an
// error naming the file to fix.
#ifndef ISPQ_SERVER_HTTP_HTTP_TLS_H_
#define ISPQ_SERVER_HTTP_HTTP_TLS_H_

#include <string>

#include "absl/status/statusor.h"

namespace ispq::server::http {

// PEM text, as libmicrohttpd takes it (MHD_OPTION_HTTPS_MEM_CERT, MHD_OPTION_HTTPS_MEM_KEY).
struct HttpTlsMaterial {
  std::string cert_pem;  // the server's certificate chain, leaf first
  std::string key_pem;   // its private key
};

// NOT_FOUND naming a file that cannot be opened; INVALID_ARGUMENT naming a file that is too large
// for PEM, holds no certificate or no usable key, or a key that does not match the certificate.
absl::StatusOr<HttpTlsMaterial> LoadHttpTlsMaterial(const std::string& cert_file,
                                                    const std::string& key_file);

// Whether this libmicrohttpd can serve HTTPS (Debian's is built with GnuTLS; a build without it
// could only fail later, with no reason given).
bool HttpTlsSupported();

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_TLS_H_
