// swum admittance's report: a diverged point is marked in the CSV and the JSON (not passed off
// as data), and a level with diverged points or a failed fit is named in one line.
#include "output/reports/model/admittance_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

namespace swum::host {
namespace {

AdmittancePoint point(double frequency_hz, bool diverged) {
  AdmittancePoint p;
  p.frequency_hz = frequency_hz;
  p.amplitude_v = 300.0;
  p.current_a = 0.75;
  p.magnitude_siemens = 0.0025;
  p.phase_deg = 80.0;
  p.conductance_siemens = 0.0005;
  p.susceptance_siemens = 0.0024;
  p.diverged = diverged;
  return p;
}

AdmittanceReport report(bool diverged, bool fit_ok) {
  AdmittanceReport r;
  r.source = "motor.toml";
  AdmittanceLevel level;
  level.amplitude_v = 300.0;
  level.points = {point(39000.0, false), point(39100.0, diverged)};
  level.fit.ok = fit_ok;
  level.fit.failure = fit_ok ? "" : "fewer than 8 usable points";
  r.levels.push_back(level);
  return r;
}

TEST(AdmittanceReport, ADivergedPointIsMarkedInTheCsvAndTheJson) {
  const AdmittanceReport r = report(true, false);
  EXPECT_EQ(admittance_csv(r),
            "amplitude_v,frequency_hz,magnitude_siemens,phase_deg,conductance_siemens,susceptance_siemens,current_a,"
            "diverged\n"
            "300,39000,0.0025,80.000000,0.0005,0.0024,0.75,0\n"
            "300,39100,0.0025,80.000000,0.0005,0.0024,0.75,1\n");
  const auto j = nlohmann::json::parse(admittance_json(r));
  const auto& points = j.at("levels").at(0).at("points");
  EXPECT_FALSE(points.at(0).at("diverged").get<bool>());
  EXPECT_TRUE(points.at(1).at("diverged").get<bool>());
  EXPECT_EQ(points.at(1).at("current_a"), 0.75);
}

TEST(AdmittanceReport, DivergedPointsOrAFailedFitAreNamedInOneLine) {
  const std::string diverged = admittance_problem(report(true, true));
  EXPECT_EQ(diverged.rfind("admittance at 300 V: 1 of 2 points diverged", 0), 0u) << diverged;
  const std::string failed = admittance_problem(report(false, false));
  EXPECT_EQ(failed, "admittance at 300 V: the circuit fit failed: fewer than 8 usable points");
  EXPECT_EQ(admittance_problem(report(false, true)), "");
  for (const std::string& line : {diverged, failed}) EXPECT_EQ(line.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace swum::host
