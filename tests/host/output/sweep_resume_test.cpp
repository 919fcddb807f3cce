// `swum sweep --resume` (host/output/sweep_resume.h): what an OUT.partial may be continued from,
// and the one-line errors for a file of another sweep.
#include "output/sweep_resume.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "commands/command_error.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

std::filesystem::path fresh_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "swum_sweep_resume_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::filesystem::remove(path);
  std::filesystem::remove(partial_path(path));
  return path;
}

SweepRow point(double amplitude_v, double frequency_hz) {
  SweepRow r;
  r.amplitude_v = amplitude_v;
  r.frequency_hz = frequency_hz;
  r.ok = true;
  r.speed_mm_s = 10.0;
  return r;
}

const std::vector<SweepRow> kPlanned = {point(100, 40000), point(100, 39950), point(200, 40000)};

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const CommandError& e) {
    return e.what();
  }
  return "";
}

TEST(ReadSweepPartial, KeepsTheRowsAtThePlannedPointsAndTheirBytes) {
  const auto path = fresh_path("kept.csv");
  const std::string header = format_sweep_header(kModelSweep);
  const std::string row0 = format_sweep_row(kModelSweep, kPlanned[0]);
  const std::string row1 = format_sweep_row(kModelSweep, kPlanned[1]);
  write_text_file_atomically(partial_path(path), header + row0 + row1);
  const SweepKept kept = read_sweep_partial(path.string(), header, kPlanned);
  ASSERT_EQ(kept.rows.size(), 2u);
  ASSERT_EQ(kept.lines.size(), 3u);
  EXPECT_DOUBLE_EQ(kept.rows[1].frequency_hz, 39950.0);
  EXPECT_EQ(kept.bytes(0), header.size());
  EXPECT_EQ(kept.bytes(1), header.size() + row0.size());
  EXPECT_EQ(kept.bytes(2), header.size() + row0.size() + row1.size());
}

TEST(ReadSweepPartial, AnEmptyPartialStartsAfresh) {
  const auto path = fresh_path("empty.csv");
  write_text_file_atomically(partial_path(path), "");
  const SweepKept kept = read_sweep_partial(path.string(), format_sweep_header(kModelSweep), kPlanned);
  EXPECT_TRUE(kept.rows.empty());
  EXPECT_TRUE(kept.lines.empty());
}

TEST(ReadSweepPartial, NamesWhatDoesNotBelongToThisSweep) {
  const auto path = fresh_path("other.csv");
  const std::string partial = partial_path(path).string();
  const std::string header = format_sweep_header(kModelSweep);
  write_text_file_atomically(partial_path(path), format_sweep_header(kDeviceSweep));
  EXPECT_EQ(message_of([&] { read_sweep_partial(path.string(), header, kPlanned); }),
            "--resume: " + partial + " does not start with this sweep's header (a device sweep, or not a sweep file?)");
  write_text_file_atomically(partial_path(path), header + format_sweep_row(kModelSweep, kPlanned[1]));
  EXPECT_EQ(message_of([&] { read_sweep_partial(path.string(), header, kPlanned); }),
            "--resume: row 1 of " + partial +
                " is not at this sweep's point 1 (amplitude_v,frequency_hz,load_n 100,40000,0): other --amplitude-v, "
                "--frequency-hz or "
                "--load?");
  write_text_file_atomically(partial_path(path), header + format_sweep_row(kModelSweep, kPlanned[0]));
  EXPECT_EQ(message_of([&] { read_sweep_partial(path.string(), header, {}); }),
            "--resume: " + partial +
                " has 1 rows, more than the points of this sweep (0): other --amplitude-v, --frequency-hz or --load?");
}

TEST(RefuseToOverwriteSweepPartial, OnlyWhenThePartialHoldsARow) {
  const auto path = fresh_path("fresh.csv");
  EXPECT_NO_THROW(refuse_to_overwrite_sweep_partial(path.string()));  // no partial at all
  write_text_file_atomically(partial_path(path), format_sweep_header(kModelSweep));
  EXPECT_NO_THROW(refuse_to_overwrite_sweep_partial(path.string()));  // a header only
  write_text_file_atomically(partial_path(path),
                             format_sweep_header(kModelSweep) + format_sweep_row(kModelSweep, kPlanned[0]));
  EXPECT_EQ(message_of([&] { refuse_to_overwrite_sweep_partial(path.string()); }),
            partial_path(path).string() +
                " holds an unfinished sweep: continue it with --resume, or delete it to start afresh");
}

}  // namespace
}  // namespace swum::host
