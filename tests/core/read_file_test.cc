// SPDX-License-Identifier: Apache-2.0
// ReadFileToString: the bytes exactly as stored, the size limit checked before reading (a file
// of exactly the limit passes, one byte more does not), and errors that name the file.
#include "core/read_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

class ReadFileTest : public ::testing::Test {
 protected:
  ReadFileTest() {
    dir_ = std::filesystem::temp_directory_path() /
           ("ispq-read-file-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  ~ReadFileTest() override { std::filesystem::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  std::filesystem::path dir_;
};

TEST_F(ReadFileTest, ReturnsTheBytesExactly) {
  const std::string bytes("a\0b\r\n\xff end", 10);
  const absl::StatusOr<std::string> read = ReadFileToString(Write("binary", bytes), 1 << 10);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(*read, bytes);
  EXPECT_EQ(*ReadFileToString(Write("empty", ""), 0), "");
}

TEST_F(ReadFileTest, TheLimitIsInclusive) {
  const std::string path = Write("ten", "0123456789");
  EXPECT_EQ(*ReadFileToString(path, 10), "0123456789");
  const absl::StatusOr<std::string> over = ReadFileToString(path, 9);
  EXPECT_EQ(over.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(over.status().message(), path + ": file has 10 bytes, more than the limit of 9");
}

TEST_F(ReadFileTest, AMissingFileIsNotFoundAndNamed) {
  const std::string path = (dir_ / "missing").string();
  const absl::StatusOr<std::string> read = ReadFileToString(path, 1 << 10);
  EXPECT_EQ(read.status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(read.status().message(), path + ": cannot open file");
}

// A directory opens like a file on Linux; it must be refused, not read as some bytes.
TEST_F(ReadFileTest, ADirectoryIsRefusedAndNamed) {
  const std::string path = dir_.string();
  const absl::StatusOr<std::string> read = ReadFileToString(path, size_t{1} << 40);
  EXPECT_FALSE(read.ok());
  EXPECT_THAT(std::string(read.status().message()), HasSubstr(path + ": "));
}

}  // namespace
}  // namespace ispq
