// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_tls.h"

#include <gnutls/gnutls.h>
#include <gnutls/x509.h>
#include <microhttpd.h>

#include <memory>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/read_file.h"

namespace ispq::server::http {
namespace {

// PEM files are small; a wrong path to a large file is refused before it is read whole.
constexpr size_t kMaxPemBytes = 1 << 20;

gnutls_datum_t Datum(const std::string& text) {
  return {reinterpret_cast<unsigned char*>(const_cast<char*>(text.data())),
          static_cast<unsigned int>(text.size())};
}

absl::Status CheckCertificate(const std::string& file, const std::string& pem) {
  gnutls_x509_crt_t* certificates = nullptr;
  unsigned int count = 0;
  const gnutls_datum_t data = Datum(pem);
  const int imported =
      gnutls_x509_crt_list_import2(&certificates, &count, &data, GNUTLS_X509_FMT_PEM, 0);
  for (unsigned int i = 0; i < count; ++i) gnutls_x509_crt_deinit(certificates[i]);
  gnutls_free(certificates);
  if (imported < 0 || count == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(file, " holds no PEM certificate for the HTTP side's TLS (GnuTLS: ",
                     imported < 0 ? gnutls_strerror(imported) : "no certificate", ")"));
  }
  return absl::OkStatus();
}

absl::Status CheckKey(const std::string& file, const std::string& pem) {
  gnutls_x509_privkey_t key = nullptr;
  if (gnutls_x509_privkey_init(&key) < 0) return absl::ResourceExhaustedError("GnuTLS key");
  const gnutls_datum_t data = Datum(pem);
  // No password: the server has none to give (an encrypted key is refused here, by name).
  const int imported = gnutls_x509_privkey_import2(key, &data, GNUTLS_X509_FMT_PEM, nullptr, 0);
  gnutls_x509_privkey_deinit(key);
  if (imported < 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        file, " holds no unencrypted PEM private key for the HTTP side's TLS (GnuTLS: ",
        gnutls_strerror(imported), ")"));
  }
  return absl::OkStatus();
}

// What libmicrohttpd will do with the two: load them as one credential, which also checks that
// the key is the certificate's.
absl::Status CheckPair(const std::string& cert_file, const std::string& key_file,
                       const HttpTlsMaterial& material) {
  gnutls_certificate_credentials_t credentials = nullptr;
  if (gnutls_certificate_allocate_credentials(&credentials) < 0) {
    return absl::ResourceExhaustedError("GnuTLS credentials");
  }
  const gnutls_datum_t cert = Datum(material.cert_pem);
  const gnutls_datum_t key = Datum(material.key_pem);
  const int loaded = gnutls_certificate_set_x509_key_mem2(credentials, &cert, &key,
                                                          GNUTLS_X509_FMT_PEM, nullptr, 0);
  gnutls_certificate_free_credentials(credentials);
  if (loaded == GNUTLS_E_CERTIFICATE_KEY_MISMATCH) {
    return absl::InvalidArgumentError(absl::StrCat("the private key in ", key_file,
                                                   " does not belong to the certificate in ",
                                                   cert_file, " (HTTP side's TLS)"));
  }
  if (loaded < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(cert_file, " and ", key_file,
                     " cannot serve TLS on the HTTP side (GnuTLS: ", gnutls_strerror(loaded), ")"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<HttpTlsMaterial> LoadHttpTlsMaterial(const std::string& cert_file,
                                                    const std::string& key_file) {
  HttpTlsMaterial material;
  absl::StatusOr<std::string> cert = ReadFileToString(cert_file, kMaxPemBytes);
  if (!cert.ok()) return cert.status();
  material.cert_pem = *std::move(cert);
  absl::StatusOr<std::string> key = ReadFileToString(key_file, kMaxPemBytes);
  if (!key.ok()) return key.status();
  material.key_pem = *std::move(key);
  if (absl::Status status = CheckCertificate(cert_file, material.cert_pem); !status.ok()) {
    return status;
  }
  if (absl::Status status = CheckKey(key_file, material.key_pem); !status.ok()) return status;
  if (absl::Status status = CheckPair(cert_file, key_file, material); !status.ok()) return status;
  return material;
}

bool HttpTlsSupported() { return MHD_is_feature_supported(MHD_FEATURE_TLS) == MHD_YES; }

}  // namespace ispq::server::http
