// Kill-safe row files (host/output/partial_file.h): rows go to NAME.partial, NAME appears only
// by the rename at the end, a resumed file keeps exactly the bytes asked for, and rows that
// complete out of order are written in order.
#include "output/partial_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <thread>

#include "commands/command_error.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

std::filesystem::path fresh_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "swum_partial_file_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::filesystem::remove(path);
  std::filesystem::remove(partial_path(path));
  return path;
}

TEST(PartialFile, RowsGoToThePartialAndTheRenameMakesTheFile) {
  const auto path = fresh_path("a.csv");
  write_text_file_atomically(path, "old\n");  // an older result stays until the new one is whole
  PartialFile file(path, "x,y\n");
  EXPECT_EQ(file.partial(), path.string() + ".partial");
  file.append("1,2\n");
  // Each row is in the file at once (no buffer a SIGKILL could lose).
  EXPECT_EQ(read_text_file(partial_path(path)), "x,y\n1,2\n");
  EXPECT_EQ(read_text_file(path), "old\n");
  file.append("3,4\n");
  file.commit();
  EXPECT_EQ(read_text_file(path), "x,y\n1,2\n3,4\n");
  EXPECT_FALSE(std::filesystem::exists(partial_path(path)));
}

TEST(PartialFile, AnUnfinishedRunLeavesThePartial) {
  const auto path = fresh_path("b.csv");
  {
    PartialFile file(path, "x\n");
    file.append("1\n");
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(read_text_file(partial_path(path)), "x\n1\n");
}

TEST(PartialFile, DiscardLeavesNothing) {
  const auto path = fresh_path("c.csv");
  PartialFile file(path, "x\n");
  file.discard();
  EXPECT_FALSE(std::filesystem::exists(partial_path(path)));
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(PartialFile, ResumeKeepsTheBytesAskedForAndAppends) {
  const auto path = fresh_path("d.csv");
  write_text_file_atomically(partial_path(path), "x\n1\n2\n3");  // "3" was cut short
  const std::vector<std::string> lines = read_partial_lines(path);
  EXPECT_EQ(lines, (std::vector<std::string>{"x", "1", "2"}));
  PartialFile file = PartialFile::resume(path, 4);  // "x\n1\n": row "2" is to be done again
  file.append("2b\n");
  file.commit();
  EXPECT_EQ(read_text_file(path), "x\n1\n2b\n");
}

TEST(PartialFile, ErrorsNameTheFileAndTheCause) {
  try {
    read_partial_lines(fresh_path("none.csv"));
    FAIL();
  } catch (const CommandError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("none.csv.partial"), std::string::npos) << message;
    EXPECT_NE(message.find("--resume"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line";
  }
  EXPECT_THROW(PartialFile("/nonexistent/out.csv", "x\n"), CommandError);
  // The rename fails when NAME is a non-empty directory: reported with errno's text.
  const auto path = fresh_path("dir.csv");
  std::filesystem::create_directories(path / "inside");
  PartialFile file(path, "x\n");
  try {
    file.commit();
    FAIL();
  } catch (const CommandError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot rename"), std::string::npos) << message;
    EXPECT_NE(message.find("Is a directory"), std::string::npos) << message;
  }
  std::filesystem::remove_all(path);
}

TEST(InOrderRows, RowsCompletedInAnyOrderAreWrittenInOrder) {
  const auto path = fresh_path("e.csv");
  PartialFile file(path, "i\n");
  InOrderRows rows(file, 0);
  rows.complete(1, "1\n");
  rows.complete(2, "2\n");
  EXPECT_EQ(rows.written(), 0u);
  EXPECT_EQ(read_text_file(partial_path(path)), "i\n") << "row 0 is not done: nothing may go out";
  rows.complete(0, "0\n");
  EXPECT_EQ(rows.written(), 3u);
  EXPECT_EQ(read_text_file(partial_path(path)), "i\n0\n1\n2\n");
  rows.complete(4, "4\n");
  EXPECT_EQ(read_text_file(partial_path(path)), "i\n0\n1\n2\n");
  EXPECT_THROW(rows.complete(1, "1\n"), std::logic_error);
}

TEST(InOrderRows, ManyThreadsGiveTheSerialFile) {
  const auto path = fresh_path("f.csv");
  constexpr std::size_t kRows = 2000, kFirst = 5;
  std::vector<std::size_t> order;
  for (std::size_t i = kFirst; i < kRows; ++i) order.push_back(i);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  PartialFile file(path, "i\n");
  InOrderRows rows(file, kFirst);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t k = t; k < order.size(); k += 4) rows.complete(order[k], std::to_string(order[k]) + "\n");
    });
  }
  for (auto& thread : threads) thread.join();
  file.commit();
  std::string expected = "i\n";
  for (std::size_t i = kFirst; i < kRows; ++i) expected += std::to_string(i) + "\n";
  EXPECT_EQ(read_text_file(path), expected);
  EXPECT_EQ(rows.written(), kRows);
}

}  // namespace
}  // namespace swum::host
