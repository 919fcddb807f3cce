#include "output/text_files.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "commands/command_error.h"

namespace swum::host {
namespace {

TEST(TextFiles, RoundTripAndNoTemporaryLeft) {
  const auto dir = std::filesystem::temp_directory_path() / "swum_text_files_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / "a.csv";
  write_text_file_atomically(path, "x,y\n1,2\n");
  EXPECT_EQ(read_text_file(path), "x,y\n1,2\n");
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

TEST(TextFiles, MissingFileNamesPathAndReason) {
  try {
    read_text_file("/nonexistent/motor.toml");
    FAIL();
  } catch (const CommandError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("/nonexistent/motor.toml"), std::string::npos);
    EXPECT_NE(message.find("No such file"), std::string::npos) << message;
  }
}

TEST(TextFiles, DirectoryIsNotAFile) {
  EXPECT_THROW(read_text_file(std::filesystem::temp_directory_path()), CommandError);
}

TEST(TextFiles, UnwritableTargetIsAnError) {
  EXPECT_THROW(write_text_file_atomically("/nonexistent/out.csv", "x"), CommandError);
}

}  // namespace
}  // namespace swum::host
