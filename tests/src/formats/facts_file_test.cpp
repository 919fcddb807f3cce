// The facts file of `swum calibrate --facts`: the paper's facts in config/ load, the defaults
// and bands are the documented ones, and every reject is one message naming the file, the
// line of the [[fact]] table and what is wrong.
#include "formats/facts_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "model/parameters.h"
#include "test_paths.h"

namespace swum {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A valid fact of six lines: a bad fact appended after it starts on line 7.
const std::string kGoodFact = "[[fact]]\n"
                              "kind = \"speed\"\n"
                              "paper_v = 100\n"
                              "frequency_hz = 40000\n"
                              "target = 10\n"
                              "tolerance = 1\n";

// The message of parsing `text` as facts.toml, or "" when it loads.
std::string error_of(const std::string& text) {
  try {
    (void)parse_facts(text, "facts.toml");
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

TEST(FactsFile, ThePapersFactsLoad) {
  const std::string path = swum::test::source_path("config/li2019_facts.toml");
  const std::string text = read(path);
  ASSERT_FALSE(text.empty()) << path;
  const std::vector<Fact> facts = parse_facts(text, path);
  ASSERT_EQ(facts.size(), 7u);

  EXPECT_EQ(facts[0].id, "E8 dead-zone onset at 40 kHz");
  EXPECT_EQ(facts[0].kind, FactKind::dead_zone_onset);
  EXPECT_EQ(facts[0].frequency_hz, 40000.0);
  EXPECT_EQ(facts[0].threshold_mm_s, 2.0);
  EXPECT_FALSE(facts[0].target.has_value());
  EXPECT_EQ(facts[0].min, -kInfinity);
  EXPECT_EQ(facts[0].max, 50.0);
  EXPECT_EQ(facts[0].tolerance, 10.0);
  EXPECT_EQ(facts[0].centre(), 50.0);
  EXPECT_EQ(facts[0].unit(), "V");

  // The dead zone as the validation tests state it: still at 40 Vpp, moving at 75 Vpp.
  EXPECT_EQ(facts[1].kind, FactKind::speed);
  EXPECT_EQ(facts[1].paper_v, 40.0);
  EXPECT_EQ(facts[1].min, -1.0);
  EXPECT_EQ(facts[1].max, 1.0);
  EXPECT_EQ(facts[2].kind, FactKind::speed);
  EXPECT_EQ(facts[2].paper_v, 75.0);
  EXPECT_EQ(facts[2].min, 2.0);
  EXPECT_EQ(facts[2].max, kInfinity);
  EXPECT_EQ(facts[2].unit(), "mm/s");

  EXPECT_EQ(facts[3].kind, FactKind::saturation_ratio);
  EXPECT_EQ(facts[3].max, 0.5);
  EXPECT_EQ(facts[3].tolerance, 0.05);
  EXPECT_EQ(facts[3].unit(), "");

  const double peaks[] = {40400.0, 40200.0, 39600.0};
  const double voltages[] = {100.0, 250.0, 400.0};
  for (std::size_t k = 0; k < 3; ++k) {
    const Fact& f = facts[4 + k];
    EXPECT_EQ(f.kind, FactKind::peak_frequency) << f.id;
    EXPECT_EQ(f.paper_v, voltages[k]) << f.id;
    ASSERT_TRUE(f.target.has_value()) << f.id;
    EXPECT_EQ(*f.target, peaks[k]) << f.id;
    EXPECT_EQ(f.min, peaks[k] - 200.0) << f.id;
    EXPECT_EQ(f.max, peaks[k] + 200.0) << f.id;
    EXPECT_EQ(f.unit(), "Hz") << f.id;
  }
  EXPECT_EQ(facts[5].id, "E10 peak at 250 Vpp");
  // Lines of the [[fact]] headers, ascending.
  EXPECT_GT(facts[0].line, 1);
  for (std::size_t k = 1; k < facts.size(); ++k) EXPECT_GT(facts[k].line, facts[k - 1].line);
}

TEST(FactsFile, DefaultsAreTheDocumentedOnes) {
  const std::vector<Fact> facts = parse_facts("[[fact]]\n"
                                              "kind = \"peak_frequency\"\n"
                                              "paper_v = 250\n"
                                              "target = 40200\n"
                                              "tolerance = 200\n"
                                              "[[fact]]\n"
                                              "kind = \"dead_zone_onset\"\n"
                                              "frequency_hz = 40000\n"
                                              "max = 50\n"
                                              "tolerance = 10\n"
                                              "[[fact]]\n"
                                              "kind = \"saturation_ratio\"\n"
                                              "frequency_hz = 40000\n"
                                              "max = 0.5\n"
                                              "tolerance = 0.05\n"
                                              "[[fact]]\n"
                                              "kind = \"speed\"\n"
                                              "paper_v = 200\n"
                                              "frequency_hz = 40000\n"
                                              "min = 20\n"
                                              "tolerance = 5\n",
                                              "facts.toml");
  ASSERT_EQ(facts.size(), 4u);

  const Fact& peak = facts[0];
  EXPECT_EQ(peak.kind, FactKind::peak_frequency);
  EXPECT_EQ(peak.line, 1);
  EXPECT_EQ(peak.id, "peak_frequency (line 1)");
  EXPECT_EQ(peak.load_n, 0.0);
  EXPECT_EQ(peak.search_hz[0], 39000.0);
  EXPECT_EQ(peak.search_hz[1], 41000.0);
  EXPECT_EQ(peak.search_hz[2], 100.0);

  const Fact& onset = facts[1];
  EXPECT_EQ(onset.kind, FactKind::dead_zone_onset);
  EXPECT_EQ(onset.line, 6);
  EXPECT_EQ(onset.id, "dead_zone_onset (line 6)");
  EXPECT_EQ(onset.load_n, 0.0);
  EXPECT_EQ(onset.threshold_mm_s, 2.0);
  EXPECT_EQ(onset.search_paper_v[0], 10.0);
  EXPECT_EQ(onset.search_paper_v[1], 200.0);

  const Fact& ratio = facts[2];
  EXPECT_EQ(ratio.kind, FactKind::saturation_ratio);
  EXPECT_EQ(ratio.id, "saturation_ratio (line 11)");
  EXPECT_EQ(ratio.ratio_paper_v[0], 100.0);
  EXPECT_EQ(ratio.ratio_paper_v[1], 200.0);
  EXPECT_EQ(ratio.ratio_paper_v[2], 300.0);
  EXPECT_EQ(ratio.ratio_paper_v[3], 400.0);

  const Fact& speed = facts[3];
  EXPECT_EQ(speed.kind, FactKind::speed);
  EXPECT_EQ(speed.id, "speed (line 16)");
  EXPECT_EQ(speed.load_n, 0.0);
  EXPECT_EQ(speed.unit(), "mm/s");
}

TEST(FactsFile, GivenKeysOverrideTheDefaults) {
  const std::vector<Fact> facts = parse_facts("[[fact]]\n"
                                              "id = \"loaded peak\"\n"
                                              "kind = \"peak_frequency\"\n"
                                              "paper_v = 250\n"
                                              "load_n = 1.5\n"
                                              "search_hz = [38000, 42000.0, 50]\n"
                                              "target = 40200\n"
                                              "tolerance = 200\n"
                                              "[[fact]]\n"
                                              "kind = \"dead_zone_onset\"\n"
                                              "frequency_hz = 41000\n"
                                              "load_n = -2\n"
                                              "threshold_mm_s = 0.5\n"
                                              "search_paper_v = [5, 300]\n"
                                              "max = 50\n"
                                              "tolerance = 10\n"
                                              "[[fact]]\n"
                                              "kind = \"saturation_ratio\"\n"
                                              "frequency_hz = 40000\n"
                                              "paper_v = [50, 150.5, 250, 450]\n"
                                              "max = 0.5\n"
                                              "tolerance = 0.05\n",
                                              "facts.toml");
  ASSERT_EQ(facts.size(), 3u);
  EXPECT_EQ(facts[0].id, "loaded peak");
  EXPECT_EQ(facts[0].load_n, 1.5);
  EXPECT_EQ(facts[0].search_hz[0], 38000.0);
  EXPECT_EQ(facts[0].search_hz[1], 42000.0);
  EXPECT_EQ(facts[0].search_hz[2], 50.0);
  EXPECT_EQ(facts[1].frequency_hz, 41000.0);
  EXPECT_EQ(facts[1].load_n, -2.0);
  EXPECT_EQ(facts[1].threshold_mm_s, 0.5);
  EXPECT_EQ(facts[1].search_paper_v[0], 5.0);
  EXPECT_EQ(facts[1].search_paper_v[1], 300.0);
  EXPECT_EQ(facts[2].ratio_paper_v[0], 50.0);
  EXPECT_EQ(facts[2].ratio_paper_v[1], 150.5);
  EXPECT_EQ(facts[2].ratio_paper_v[2], 250.0);
  EXPECT_EQ(facts[2].ratio_paper_v[3], 450.0);
}

TEST(FactsFile, IntegersAndFloatsAreTheSameNumbers) {
  const auto as_integers = parse_facts(kGoodFact, "a.toml");
  const auto as_floats = parse_facts(
      "[[fact]]\nkind = \"speed\"\npaper_v = 100.0\nfrequency_hz = 4.0e4\ntarget = 10.0\ntolerance = 1.0\n", "b.toml");
  ASSERT_EQ(as_integers.size(), 1u);
  ASSERT_EQ(as_floats.size(), 1u);
  EXPECT_EQ(as_integers[0].paper_v, 100.0);
  EXPECT_EQ(as_integers[0].frequency_hz, 40000.0);
  EXPECT_EQ(as_integers[0].paper_v, as_floats[0].paper_v);
  EXPECT_EQ(as_integers[0].frequency_hz, as_floats[0].frequency_hz);
  EXPECT_EQ(as_integers[0].target, as_floats[0].target);
  EXPECT_EQ(as_integers[0].tolerance, as_floats[0].tolerance);
}

TEST(FactsFile, TargetGivesTheBandTargetPlusMinusTolerance) {
  const auto facts = parse_facts(kGoodFact, "facts.toml");
  ASSERT_EQ(facts.size(), 1u);
  const Fact& f = facts[0];
  ASSERT_TRUE(f.target.has_value());
  EXPECT_EQ(*f.target, 10.0);
  EXPECT_EQ(f.tolerance, 1.0);
  EXPECT_EQ(f.min, 9.0);
  EXPECT_EQ(f.max, 11.0);
  EXPECT_EQ(f.centre(), 10.0);
}

TEST(FactsFile, MinAndMaxGiveOneOrTwoSidedBands) {
  const auto band = [](const std::string& bounds) {
    const auto facts = parse_facts(
        "[[fact]]\nkind = \"speed\"\npaper_v = 100\nfrequency_hz = 40000\ntolerance = 2\n" + bounds, "facts.toml");
    EXPECT_EQ(facts.size(), 1u);
    return facts.at(0);
  };
  const Fact above = band("min = 20\n");
  EXPECT_FALSE(above.target.has_value());
  EXPECT_EQ(above.min, 20.0);
  EXPECT_EQ(above.max, kInfinity);
  EXPECT_EQ(above.tolerance, 2.0);
  EXPECT_EQ(above.centre(), 20.0);

  const Fact below = band("max = 30\n");
  EXPECT_EQ(below.min, -kInfinity);
  EXPECT_EQ(below.max, 30.0);
  EXPECT_EQ(below.centre(), 30.0);

  const Fact both = band("min = 20\nmax = 30\n");
  EXPECT_EQ(both.min, 20.0);
  EXPECT_EQ(both.max, 30.0);
  EXPECT_EQ(both.centre(), 25.0);

  const Fact point = band("min = 20\nmax = 20\n");  // min = max is a (closed) band
  EXPECT_EQ(point.min, 20.0);
  EXPECT_EQ(point.max, 20.0);
  EXPECT_EQ(point.centre(), 20.0);
}

TEST(FactsFile, KindNamesAndUnits) {
  EXPECT_EQ(fact_kind_name(FactKind::peak_frequency), "peak_frequency");
  EXPECT_EQ(fact_kind_name(FactKind::dead_zone_onset), "dead_zone_onset");
  EXPECT_EQ(fact_kind_name(FactKind::saturation_ratio), "saturation_ratio");
  EXPECT_EQ(fact_kind_name(FactKind::speed), "speed");
  Fact f;
  f.kind = FactKind::peak_frequency;
  EXPECT_EQ(f.unit(), "Hz");
  f.kind = FactKind::dead_zone_onset;
  EXPECT_EQ(f.unit(), "V");
  f.kind = FactKind::saturation_ratio;
  EXPECT_EQ(f.unit(), "");
  f.kind = FactKind::speed;
  EXPECT_EQ(f.unit(), "mm/s");
}

TEST(FactsFile, RejectsAreOneLineWithFileLineAndWhat) {
  struct Case {
    std::string text;
    const char* expected;
  };
  // Each bad fact follows kGoodFact, so its table starts on line 7.
  const std::string peak = kGoodFact + "[[fact]]\nkind = \"peak_frequency\"\npaper_v = 250\ntarget = 40200\n";
  const std::string onset = kGoodFact + "[[fact]]\nkind = \"dead_zone_onset\"\nfrequency_hz = 40000\nmax = 50\n";
  const std::string ratio = kGoodFact + "[[fact]]\nkind = \"saturation_ratio\"\nfrequency_hz = 40000\nmax = 0.5\n";
  const std::string speed = kGoodFact + "[[fact]]\nkind = \"speed\"\npaper_v = 100\nfrequency_hz = 40000\n";
  const Case cases[] = {
      // TOML errors, at the line of the error.
      {kGoodFact + "[[fact]\n", "facts.toml:7: TOML syntax error: Error while parsing table header"},
      {kGoodFact + "[[fact]]\nkind = \"speed\"\npaper_v = = 3\n",
       "facts.toml:9: TOML syntax error: Error while parsing value"},
      // Control characters of the file are shown as \xNN: the message stays one line (fuzz finding).
      {kGoodFact + "[[fact]]\nkind = \"peak\\nfrequency\"\n", "facts.toml:7: unknown kind 'peak\\x0afrequency'"},
      {kGoodFact + "[[fact]]\nkind = n\nan\n", "facts.toml:8: TOML syntax error: "},
      // No [[fact]] table, or something else beside them.
      {"# nothing\n", "facts.toml: no [[fact]] table"},
      {"fact = []\n", "facts.toml: no [[fact]] table"},
      {kGoodFact + "[facts]\nkind = \"speed\"\n", "facts.toml:7: unknown table or key 'facts'"},
      {"title = \"x\"\n" + kGoodFact, "facts.toml:1: unknown table or key 'title'"},
      {"fact = [1, 2]\n", "facts.toml:1: fact: expected a table"},
      // The kind.
      {kGoodFact + "[[fact]]\npaper_v = 100\n", "facts.toml:7: fact needs kind"},
      {kGoodFact + "[[fact]]\nkind = 3\n", "facts.toml:7: kind: expected a string"},
      {kGoodFact + "[[fact]]\nkind = \"peak\"\npaper_v = 100\n", "facts.toml:7: unknown kind 'peak'"},
      // Unknown keys, also those of another kind.
      {peak + "tolerance = 200\nvolts = 3\n", "facts.toml:7: unknown key 'volts'"},
      {peak + "tolerance = 200\nfrequency_hz = 40000\n", "facts.toml:7: unknown key 'frequency_hz'"},
      {speed + "target = 1\ntolerance = 1\nthreshold_mm_s = 2\n", "facts.toml:7: unknown key 'threshold_mm_s'"},
      {ratio + "tolerance = 0.05\nload_n = 1\n", "facts.toml:7: unknown key 'load_n'"},
      // The retired voltage keys, named with their new spelling.
      {kGoodFact + "[[fact]]\nkind = \"speed\"\nvpp = 100\nfrequency_hz = 40000\ntarget = 1\ntolerance = 1\n",
       "facts.toml:7: vpp: retired key; give the voltage as the source quotes it as paper_v (read through "
       "options.paper_voltage_axis)"},
      {onset + "tolerance = 10\nsearch_vpp = [10, 200]\n",
       "facts.toml:7: search_vpp: retired key; give the voltage as the source quotes it as search_paper_v"},
      // Missing or non-numeric required keys.
      {kGoodFact + "[[fact]]\nkind = \"peak_frequency\"\ntarget = 40200\ntolerance = 200\n",
       "facts.toml:7: peak_frequency fact needs paper_v"},
      {kGoodFact + "[[fact]]\nkind = \"dead_zone_onset\"\nmax = 50\ntolerance = 10\n",
       "facts.toml:7: dead_zone_onset fact needs frequency_hz"},
      {kGoodFact + "[[fact]]\nkind = \"saturation_ratio\"\nmax = 0.5\ntolerance = 0.05\n",
       "facts.toml:7: saturation_ratio fact needs frequency_hz"},
      {kGoodFact + "[[fact]]\nkind = \"speed\"\npaper_v = 100\ntarget = 1\ntolerance = 1\n",
       "facts.toml:7: speed fact needs frequency_hz"},
      {kGoodFact + "[[fact]]\nkind = \"speed\"\nfrequency_hz = 40000\ntarget = 1\ntolerance = 1\n",
       "facts.toml:7: speed fact needs paper_v"},
      {kGoodFact + "[[fact]]\nkind = \"peak_frequency\"\npaper_v = \"250\"\ntarget = 40200\ntolerance = 200\n",
       "facts.toml:7: paper_v: expected a number"},
      {speed + "target = \"fast\"\ntolerance = 1\n", "facts.toml:7: target: expected a number"},
      {speed + "target = nan\ntolerance = 1\n", "facts.toml:7: target: not a finite number"},
      {speed + "target = 1\ntolerance = 1\nid = 7\n", "facts.toml:7: id: expected a string"},
      {peak + "tolerance = 200\nsearch_hz = [39000, 41000]\n", "facts.toml:7: search_hz: expected an array of 3"},
      {peak + "tolerance = 200\nsearch_hz = [39000, \"41000\", 100]\n",
       "facts.toml:7: search_hz: expected an array of 3"},
      {ratio + "tolerance = 0.05\npaper_v = 100\n", "facts.toml:7: paper_v: expected an array of 4"},
      // The tolerance.
      {speed + "target = 1\n", "facts.toml:7: tolerance: required, and must be > 0"},
      {speed + "target = 1\ntolerance = 0\n", "facts.toml:7: tolerance: required, and must be > 0"},
      {speed + "target = 1\ntolerance = -1\n", "facts.toml:7: tolerance: required, and must be > 0"},
      // Target or band.
      {speed + "target = 1\nmin = 0\ntolerance = 1\n", "facts.toml:7: give either target or min/max, not both"},
      {speed + "target = 1\nmax = 2\ntolerance = 1\n", "facts.toml:7: give either target or min/max, not both"},
      {speed + "tolerance = 1\n", "facts.toml:7: fact needs a target, or min and/or max"},
      {speed + "min = 3\nmax = 2\ntolerance = 1\n", "facts.toml:7: min > max"},
      // Operating points outside 1..10000 V, 1..200000 Hz (frequencies from 1 kHz), loads to 1 kN.
      {kGoodFact + "[[fact]]\nkind = \"speed\"\npaper_v = 0.5\nfrequency_hz = 40000\ntarget = 1\ntolerance = 1\n",
       "facts.toml:7: paper_v = 0.5"},
      {kGoodFact + "[[fact]]\nkind = \"peak_frequency\"\npaper_v = 20000\ntarget = 40200\ntolerance = 200\n",
       "facts.toml:7: paper_v = 20000"},
      {kGoodFact + "[[fact]]\nkind = \"speed\"\npaper_v = 100\nfrequency_hz = 300000\ntarget = 1\ntolerance = 1\n",
       "facts.toml:7: frequency_hz = 300000"},
      {kGoodFact + "[[fact]]\nkind = \"dead_zone_onset\"\nfrequency_hz = 0\nmax = 50\ntolerance = 10\n",
       "facts.toml:7: frequency_hz = 0"},
      {speed + "load_n = 5000\ntarget = 1\ntolerance = 1\n", "facts.toml:7: load_n = 5000"},
      // Search ranges that are empty or in the wrong order.
      {peak + "tolerance = 200\nsearch_hz = [41000, 39000, 100]\n", "facts.toml:7: search_hz: expected [start, stop"},
      {peak + "tolerance = 200\nsearch_hz = [39000, 41000, 0]\n", "facts.toml:7: search_hz: expected [start, stop"},
      {peak + "tolerance = 200\nsearch_hz = [39000, 41000, 3000]\n", "facts.toml:7: search_hz: expected [start, stop"},
      {peak + "tolerance = 200\nsearch_hz = [100, 41000, 100]\n", "facts.toml:7: search_hz = 100"},
      {onset + "tolerance = 10\nsearch_paper_v = [200, 10]\n", "facts.toml:7: search_paper_v: expected [low, high]"},
      {onset + "tolerance = 10\nsearch_paper_v = [10, 15]\n", "facts.toml:7: search_paper_v: expected [low, high]"},
      {onset + "tolerance = 10\nsearch_paper_v = [0.5, 100]\n", "facts.toml:7: search_paper_v: expected [low, high]"},
      {onset + "tolerance = 10\nthreshold_mm_s = 0\n", "facts.toml:7: threshold_mm_s: must be in (0, 10000]"},
      {onset + "tolerance = 10\nthreshold_mm_s = 1e300\n", "facts.toml:7: threshold_mm_s: must be in (0, 10000]"},
      // A misspelt key is named as such, not as the required key it was meant to be.
      {speed + "taget = 3\ntolerance = 1\n", "facts.toml:7: unknown key 'taget'"},
      {speed + "target = 3\ntolerence = 1\n", "facts.toml:7: unknown key 'tolerence'"},
      // A grid too fine to run at every evaluation, and a band that overflows.
      {peak + "tolerance = 200\nsearch_hz = [39000, 41000, 0.001]\n", "facts.toml:7: search_hz: more than 2000"},
      {speed + "target = 1e308\ntolerance = 1e308\n", "facts.toml:7: target +- tolerance overflows"},
      // Ratio voltages that do not increase, or lie outside 1..10000 V.
      {ratio + "tolerance = 0.05\npaper_v = [100, 300, 200, 400]\n",
       "facts.toml:7: paper_v: the four voltages must increase"},
      {ratio + "tolerance = 0.05\npaper_v = [100, 200, 200, 400]\n",
       "facts.toml:7: paper_v: the four voltages must increase"},
      {ratio + "tolerance = 0.05\npaper_v = [0, 200, 300, 400]\n", "facts.toml:7: paper_v = 0"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << "\n -> " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace swum
