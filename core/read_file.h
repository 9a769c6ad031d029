// SPDX-License-Identifier: Apache-2.0
// Reading a whole file into memory with a size limit: T-mesh and result files, the server's TLS
// certificates and keys, token files. The limit is checked before anything is read, so a huge or
// endless file is refused instead of exhausting memory; errors name the file.
#ifndef ISPQ_CORE_READ_FILE_H_
#define ISPQ_CORE_READ_FILE_H_

#include <cstddef>
#include <cstdint>
#include <string>

#include "absl/status/statusor.h"

namespace ispq {

// The file's bytes. NOT_FOUND if it cannot be opened, INVALID_ARGUMENT if it is larger than
// max_bytes or cannot be read.
absl::StatusOr<std::string> ReadFileToString(const std::string& path, size_t max_bytes);

// The INVALID_ARGUMENT ReadFileToString answers for a file of `size` bytes over `max_bytes`, for
// readers that check the size themselves.
absl::Status FileTooLargeError(const std::string& path, uint64_t size, size_t max_bytes);

}  // namespace ispq

#endif  // ISPQ_CORE_READ_FILE_H_
