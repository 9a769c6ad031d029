// SPDX-License-Identifier: Apache-2.0
#include "core/read_file.h"

#include <fstream>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq {

absl::StatusOr<std::string> ReadFileToString(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return absl::NotFoundError(absl::StrCat(path, ": cannot open file"));
  const std::streamoff size = in.tellg();
  if (size < 0) return absl::InvalidArgumentError(absl::StrCat(path, ": cannot read file"));
  if (static_cast<size_t>(size) > max_bytes) return FileTooLargeError(path, size, max_bytes);
  std::string contents(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(contents.data(), size)) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": cannot read file"));
  }
  return contents;
}

absl::Status FileTooLargeError(const std::string& path, uint64_t size, size_t max_bytes) {
  return absl::InvalidArgumentError(
      absl::StrCat(path, ": file has ", size, " bytes, more than the limit of ", max_bytes));
}

}  // namespace ispq
