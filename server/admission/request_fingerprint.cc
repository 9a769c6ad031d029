// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_fingerprint.h"

#include <openssl/evp.h>

#include <array>
#include <cstdint>
#include <memory>

#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/io/zero_copy_stream.h"

namespace ispq::server {
namespace {

// Feeds everything written through it into a SHA-256 digest, a buffer at a time.
class DigestOutputStream : public google::protobuf::io::ZeroCopyOutputStream {
 public:
  DigestOutputStream() : context_(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
    EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr);
  }

  bool Next(void** data, int* size) override {
    Flush();
    *data = buffer_.data();
    *size = static_cast<int>(buffer_.size());
    pending_ = buffer_.size();
    return true;
  }
  void BackUp(int count) override { pending_ -= static_cast<size_t>(count); }
  int64_t ByteCount() const override { return written_ + static_cast<int64_t>(pending_); }

  std::string Finish() {
    Flush();
    std::string digest(EVP_MAX_MD_SIZE, '\0');
    unsigned int length = 0;
    EVP_DigestFinal_ex(context_.get(), reinterpret_cast<unsigned char*>(digest.data()), &length);
    digest.resize(length);
    return digest;
  }

 private:
  void Flush() {
    EVP_DigestUpdate(context_.get(), buffer_.data(), pending_);
    written_ += static_cast<int64_t>(pending_);
    pending_ = 0;
  }

  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context_;
  std::array<char, 64 << 10> buffer_;
  size_t pending_ = 0;
  int64_t written_ = 0;
};

}  // namespace

std::string RequestFingerprint(const google::protobuf::MessageLite& message) {
  DigestOutputStream digest;
  {
    google::protobuf::io::CodedOutputStream output(&digest);
    output.SetSerializationDeterministic(true);
    message.ByteSizeLong();  // caches the sizes the serialization needs
    message.SerializeWithCachedSizes(&output);
  }
  return digest.Finish();
}

}  // namespace ispq::server
