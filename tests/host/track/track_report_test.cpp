// `swum track-report`'s arithmetic and readers (host/track/track_report.h): the best speed
// interpolated in the temperature rise, blocks of --block-s after --skip-s with their shares,
// the band having to cover the run, and the one-line errors of the two CSV readers naming the
// file and the line.
#include "track/track_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "track/track_run.h"

namespace swum::host {
namespace {

// Best speed 800 -> 700 -> 500 mm/s over rises 0, 10, 20 K, the speed peak 100 Hz below.
BestSpeedCurve curve() {
  BestSpeedCurve c;
  c.temperature_rise_k = {0.0, 10.0, 20.0};
  c.speed_mm_s = {800.0, 700.0, 500.0};
  c.frequency_hz = {39500.0, 39400.0, 39200.0};
  c.peak_frequency_hz = {39400.0, 39300.0, 39100.0};
  return c;
}

TEST(BestSpeedCurve, InterpolatesLinearlyBetweenRisesAndHoldsTheEnds) {
  const BestSpeedCurve c = curve();
  EXPECT_DOUBLE_EQ(c.speed_at(0.0), 800.0);
  EXPECT_DOUBLE_EQ(c.speed_at(5.0), 750.0);
  EXPECT_DOUBLE_EQ(c.speed_at(10.0), 700.0);
  EXPECT_DOUBLE_EQ(c.speed_at(15.0), 600.0);
  EXPECT_DOUBLE_EQ(c.speed_at(17.5), 550.0);
  EXPECT_DOUBLE_EQ(c.speed_at(-3.0), 800.0);
  EXPECT_DOUBLE_EQ(c.speed_at(30.0), 500.0);
  EXPECT_DOUBLE_EQ(c.frequency_at(15.0), 39300.0);
  EXPECT_DOUBLE_EQ(c.frequency_at(2.5), 39475.0);
  EXPECT_DOUBLE_EQ(c.peak_frequency_at(15.0), 39200.0);
  EXPECT_DOUBLE_EQ(c.peak_frequency_at(30.0), 39100.0);
  EXPECT_TRUE(std::isnan(BestSpeedCurve{}.speed_at(1.0)));
}

// Rows at t = 0..9 s, the stator 2 K warmer per second from 20 degC (rise 2 t). After the 2 s
// skip, blocks of 3 s are [2, 4], [5, 7], [8, 9] s with a mean best of 740, 660 and 560 mm/s
// (curve() at 4..8, 10..14, 16..18 K); the speed in each is a share of that: 0.9, 0.8, 0.98.
TrackSeries series() {
  TrackSeries run;
  run.name = "phase";
  const double block_speed[] = {0.9 * 740.0, 0.8 * 660.0, 0.98 * 560.0};
  for (int i = 0; i < 10; ++i) {
    run.time_s.push_back(i);
    run.frequency_hz.push_back(39000.0 + i);
    run.stator_temperature_c.push_back(20.0 + 2.0 * i);
    run.speed_mm_s.push_back(i < 2 ? 0.0 : block_speed[(i - 2) / 3]);
  }
  return run;
}

TEST(SummariseTrack, BlocksAfterTheSkipWithTheirSharesOfTheBestAtEachRowsRise) {
  const TrackRunSummary s = summarise_track(series(), curve(), 20.0, 2.0, 3.0);
  EXPECT_EQ(s.name, "phase");
  ASSERT_EQ(s.blocks.size(), 3u);
  const double start[] = {2, 5, 8}, end[] = {4, 7, 9}, best[] = {740, 660, 560}, rise[] = {6, 12, 17},
               share[] = {0.9, 0.8, 0.98};
  // Driven at 39000 + t Hz against the peak at each row's rise: (39002 - 39360 + 39003 - 39340 +
  // 39004 - 39320) / 3 = -337 Hz, then -254 and -151.5 Hz.
  const double margin[] = {-337.0, -254.0, -151.5};
  for (std::size_t b = 0; b < 3; ++b) {
    EXPECT_EQ(s.blocks[b].start_s, start[b]) << b;
    EXPECT_EQ(s.blocks[b].end_s, end[b]) << b;
    EXPECT_NEAR(s.blocks[b].best_speed_mm_s, best[b], 1e-9) << b;
    EXPECT_NEAR(s.blocks[b].mean_rise_k, rise[b], 1e-12) << b;
    EXPECT_NEAR(s.blocks[b].mean_speed_mm_s, share[b] * best[b], 1e-9) << b;
    EXPECT_NEAR(s.blocks[b].share, share[b], 1e-12) << b;
    EXPECT_NEAR(s.blocks[b].margin_hz, margin[b], 1e-9) << b;
  }
  EXPECT_NEAR(s.min_share, 0.8, 1e-12);
  EXPECT_NEAR(s.final_share, 0.98, 1e-12);
  EXPECT_EQ(s.final_frequency_hz, 39009.0);
  EXPECT_NEAR(s.final_margin_hz, -151.5, 1e-9);
  EXPECT_EQ(s.final_rise_k, 18.0);
  EXPECT_EQ(s.max_rise_k, 18.0);
  // One block over everything after the skip: the shares pooled by the best speed.
  const TrackRunSummary one = summarise_track(series(), curve(), 20.0, 2.0, 100.0);
  ASSERT_EQ(one.blocks.size(), 1u);
  EXPECT_NEAR(one.blocks[0].share, (3 * 0.9 * 740 + 3 * 0.8 * 660 + 2 * 0.98 * 560) / (3 * 740 + 3 * 660 + 2 * 560),
              1e-12);
  EXPECT_EQ(one.min_share, one.final_share);
  // The ambient shifts every rise: 24 degC makes the first row after the skip a 0 K rise.
  const TrackRunSummary shifted = summarise_track(series(), curve(), 24.0, 2.0, 3.0);
  EXPECT_NEAR(shifted.blocks[0].mean_rise_k, 2.0, 1e-12);
  EXPECT_NEAR(shifted.blocks[0].best_speed_mm_s, (800.0 + 780.0 + 760.0) / 3.0, 1e-9);
}

// What summarise_track refuses with, "accepted" when it does not.
std::string refusal(const TrackSeries& run, const BestSpeedCurve& best = curve(), double skip_s = 2.0,
                    double block_s = 3.0, double ambient_c = 20.0) {
  try {
    (void)summarise_track(run, best, ambient_c, skip_s, block_s);
  } catch (const std::exception& e) {  // options: invalid_argument; data: runtime_error
    return e.what();
  }
  return "accepted";
}

TEST(SummariseTrack, ARiseOutsideTheBandsGridIsRefusedNamingTheRunAndTheRise) {
  TrackSeries hot = series();
  hot.stator_temperature_c[5] = 45.5;
  EXPECT_EQ(refusal(hot), "phase: temperature rise 25.5 K at t = 5 s outside the band's 0..20 K");
  TrackSeries cold = series();
  cold.name = "speed";
  cold.stator_temperature_c[3] = 19.0;
  EXPECT_EQ(refusal(cold), "speed: temperature rise -1 K at t = 3 s outside the band's 0..20 K");
  // Inside the skipped start it does not matter.
  TrackSeries early = series();
  early.stator_temperature_c[1] = 60.0;
  EXPECT_EQ(refusal(early), "accepted");
}

TEST(SummariseTrack, ARowWithoutTemperatureAndUnusableInputsAreRefused) {
  TrackSeries gap = series();
  gap.stator_temperature_c[3] = std::nan("");
  EXPECT_EQ(refusal(gap), "phase: row 4 has no stator temperature");
  gap.stator_temperature_c[3] = 26.0;
  gap.stator_temperature_c[0] = std::nan("");  // also in the skipped start: the rise is every row's
  EXPECT_EQ(refusal(gap), "phase: row 1 has no stator temperature");
  EXPECT_EQ(refusal(series(), curve(), 2.0, 0.0), "--block-s: must be in (0, 1e6]");
  EXPECT_EQ(refusal(series(), curve(), -1.0), "--skip-s: must be in 0..1e6");
  EXPECT_EQ(refusal(series(), curve(), 2.0, 3.0, std::nan("")), "--ambient-c: must be a temperature in -1000..1000");
  EXPECT_EQ(refusal(series(), curve(), 10.0, 3.0), "phase: no rows after --skip-s");
  BestSpeedCurve single = curve();
  single.temperature_rise_k.resize(1);
  single.speed_mm_s.resize(1);
  single.frequency_hz.resize(1);
  single.peak_frequency_hz.resize(1);
  EXPECT_EQ(refusal(series(), single), "the band has fewer than two decided rises");
}

// A curve whose columns differ in length (a caller other than read_band_csv) is refused in one
// line instead of read past its end (it segfaulted before).
TEST(SummariseTrack, ACurveWhoseColumnsDifferInLengthIsRefused) {
  BestSpeedCurve no_peaks = curve();
  no_peaks.peak_frequency_hz.clear();
  EXPECT_EQ(refusal(series(), no_peaks), "the band's columns differ in length");
}

// Files in a folder of their own under the system temporary directory.
std::string write_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "swum_track_report_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

template <typename Read>
std::string error_of(Read read) {
  try {
    read();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ReadTrackCsv, ReadsWhatSwumTrackWrites) {
  TrackRow row{0,       0.02,    TrackMode::search,
               41500.0, 12.3456, protocol::ElectricalValues{0.24, 0.23, 60.0, 59.0, -12.0, -11.0, 8.0, 7.6},
               20.5,    1,       0};
  std::string text = kTrackCsvHeader + format_track_row(row);
  row.cycle = 1;
  row.time_s = 0.04;
  row.frequency_hz = 41480.0;
  row.speed_mm_s = -7.0;
  row.stator_temperature_c.reset();  // a device without the electrical port
  row.electrical.reset();
  text += format_track_row(row);
  const std::string path = write_file("written.csv", text);
  const TrackSeries run = read_track_csv(path, "fixed");
  EXPECT_EQ(run.name, "fixed");
  EXPECT_EQ(run.time_s, (std::vector<double>{0.02, 0.04}));
  EXPECT_EQ(run.frequency_hz, (std::vector<double>{41500.0, 41480.0}));
  EXPECT_EQ(run.speed_mm_s, (std::vector<double>{12.346, -7.0}));
  ASSERT_EQ(run.stator_temperature_c.size(), 2u);
  EXPECT_EQ(run.stator_temperature_c[0], 20.5);
  EXPECT_TRUE(std::isnan(run.stator_temperature_c[1]));
}

TEST(ReadTrackCsv, OnlyTheColumnsItNeedsInAnyOrderSkippingCommentsAndBlankLines) {
  const std::string path = write_file("reordered.csv",
                                      "# a comment\nstator_temperature_c,speed_mm_s,extra,frequency_hz,time_s\n\n"
                                      "21,100,x,40000,1\n# another\n22,110,y,40010,2\n");
  const TrackSeries run = read_track_csv(path, "r");
  EXPECT_EQ(run.time_s, (std::vector<double>{1, 2}));
  EXPECT_EQ(run.frequency_hz, (std::vector<double>{40000, 40010}));
  EXPECT_EQ(run.speed_mm_s, (std::vector<double>{100, 110}));
  EXPECT_EQ(run.stator_temperature_c, (std::vector<double>{21, 22}));
}

// Read as every hand-written table is (src/formats/csv_table.h, CsvLines::hand_written): a line of
// blanks, a CRLF file's empty lines and an indented comment are skipped like a blank line (they
// failed as "1 cells, the header has N" before the one table reader); line numbers still count them.
TEST(ReadTrackCsv, BlankLinesOfWhitespaceAndIndentedCommentsAreSkipped) {
  const std::string path = write_file("crlf.csv",
                                      "time_s,frequency_hz,speed_mm_s,stator_temperature_c\r\n\r\n"
                                      "1,40000,100,21\r\n  \t\n  # indented\r\n2,40010,110,22\r\n3,40020,x,23\r\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(path, "r"); }), path + ":7: speed_mm_s 'x' is not a number");
  const std::string good = write_file("crlf_good.csv", "time_s,frequency_hz,speed_mm_s,stator_temperature_c\r\n\r\n"
                                                       "1,40000,100,21\r\n  \t\n  # indented\r\n2,40010,110,22\r\n");
  const TrackSeries run = read_track_csv(good, "r");
  EXPECT_EQ(run.time_s, (std::vector<double>{1, 2}));
  EXPECT_EQ(run.speed_mm_s, (std::vector<double>{100, 110}));
}

TEST(ReadTrackCsv, OneLineErrorsNameTheFileAndTheLine) {
  const std::string header = kTrackCsvHeader;
  const std::string good = "0,0.020000,search,41500.000,1.000,,,,,,20.000,1,0\n";
  const std::string cells = write_file("cells.csv",
                                       header + good + "1,0.040000,search,41480.000,1.000,,,,,20.010,1,0\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(cells, "a"); }), cells + ":3: 12 cells, the header has 13");
  const std::string word = write_file("word.csv", header + good + "1,0.040000,search,41480.000,fast,,,,,,20.010,1,0\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(word, "a"); }), word + ":3: speed_mm_s 'fast' is not a number");
  const std::string empty_time = write_file("empty_time.csv", header + "0,,search,41500.000,1.000,,,,,,20.000,1,0\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(empty_time, "a"); }), empty_time + ":2: time_s '' is not a number");
  const std::string hot = write_file("hot.csv", header + "0,0.02,search,41500,1,,,,,,inf,1,0\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(hot, "a"); }), hot + ":2: stator_temperature_c 'inf' is not finite");
  const std::string column = write_file("column.csv", "cycle,time_s,frequency_hz,speed_mm_s\n0,0.02,41500,1\n");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(column, "a"); }), column + ": no column stator_temperature_c");
  const std::string no_rows = write_file("no_rows.csv", header);
  EXPECT_EQ(error_of([&] { (void)read_track_csv(no_rows, "a"); }), no_rows + ": no rows");
  const std::string blank = write_file("blank.csv", "");
  EXPECT_EQ(error_of([&] { (void)read_track_csv(blank, "a"); }), blank + ": empty (no header)");
  const std::string missing = (std::filesystem::path(blank).parent_path() / "missing.csv").string();
  std::filesystem::remove(missing);
  EXPECT_EQ(error_of([&] { (void)read_track_csv(missing, "a"); }), missing + ": cannot open");
}

const std::string kBandHeader =
    "amplitude_v,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,margin_hz,"
    "collapse_hz,reason\n";

TEST(ReadBandCsv, TheDecidedRowsAtTheVoltageAndLoadByRise) {
  const std::string path = write_file(
      "band.csv", kBandHeader + "400,0,50,1,39150,420.5,39050,430,100,39000,ok\n"
                                "400,0,0,1,39600,600,39500,610,100,39450,ok\n"
                                "400,0,75,0,,,,,,,speed is highest at the bottom of the sweep; widen it\n"
                                "400,0,25,1,39400,510,39300,520,100,39250,ok\n"
                                "100,0,10,1,40450,300,40350,310,100,,ok\n"
                                "400,1,10,1,39000,100,38900,110,100,,ok\n");
  const BestSpeedCurve c = read_band_csv(path, 400.0, 0.0);
  EXPECT_EQ(c.temperature_rise_k, (std::vector<double>{0, 25, 50}));
  EXPECT_EQ(c.speed_mm_s, (std::vector<double>{600, 510, 420.5}));
  EXPECT_EQ(c.frequency_hz, (std::vector<double>{39600, 39400, 39150}));
  EXPECT_EQ(c.peak_frequency_hz, (std::vector<double>{39500, 39300, 39050}));
  // Another load, and "true" as the decided cell.
  const std::string loaded = write_file("band_load.csv", kBandHeader + "400,1,0,true,39500,500,39400,510,100,,ok\n"
                                                                       "400,1,10,1,39000,100,38900,110,100,,ok\n");
  EXPECT_EQ(read_band_csv(loaded, 400.0, 1.0).temperature_rise_k, (std::vector<double>{0, 10}));
}

TEST(ReadBandCsv, OneLineErrorsNameTheFileAndTheLine) {
  const std::string row = "400,0,0,1,39600,600,39500,610,100,39450,ok\n";
  const std::string one = write_file("band_one.csv", kBandHeader + row + "400,0,25,0,,,,,,,undecided\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(one, 400.0, 0.0); }),
            one + ": fewer than two decided rows at 400 V and 0 N");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(one, 300.0, 2.5); }),
            one + ": fewer than two decided rows at 300 V and 2.5 N");
  const std::string cells = write_file("band_cells.csv", kBandHeader + row + "400,0,25,1,39400,510\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(cells, 400.0, 0.0); }), cells + ":3: 6 cells, the header has 11");
  const std::string word = write_file("band_word.csv", kBandHeader + row + "400,0,25,1,39400,quick,,,,,ok\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(word, 400.0, 0.0); }), word + ":3: speed_mm_s 'quick' is not a number");
  const std::string amplitude_v = write_file("band_amplitude_v.csv",
                                             kBandHeader + "4OO,0,0,1,39600,600,39500,610,100,39450,ok\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(amplitude_v, 400.0, 0.0); }),
            amplitude_v + ":2: amplitude_v '4OO' is not a number");
  const std::string column = write_file("band_column.csv",
                                        "amplitude_v,load_n,temperature_rise_k,frequency_hz,speed_mm_s\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(column, 400.0, 0.0); }), column + ": no column decided");
  const std::string twice = write_file("band_twice.csv",
                                       kBandHeader + row + "400,0,0,1,39610,601,39510,611,100,39460,ok\n");
  EXPECT_EQ(error_of([&] { (void)read_band_csv(twice, 400.0, 0.0); }),
            twice + ": two decided rows at a 0 K rise, 400 V and 0 N");
}

}  // namespace
}  // namespace swum::host
