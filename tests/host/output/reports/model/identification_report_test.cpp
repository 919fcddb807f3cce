#include "output/reports/model/identification_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

// Two constants identified (one significantly non-zero), two kept at their priors.
IdentificationResult small_result() {
  IdentificationResult r;
  r.ok = true;
  const char* keys[] = {"c111_pa", "c1111_pa", "e311_c_m2", "e3111_c_m2"};
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    ParameterEstimate& e = r.parameters[k];
    e.key = keys[k];
    e.prior = 1.0 + static_cast<double>(k);
  }
  r.parameters[0].identifiable = true;
  r.parameters[0].value = -2.5e12;
  r.parameters[0].standard_error = 1.2e11;
  r.parameters[0].significant = true;
  r.parameters[1].identifiable = true;
  r.parameters[1].value = 3.0e14;
  r.parameters[1].standard_error = 4.0e14;
  r.parameters[2].value = 3.0;
  r.parameters[2].reason = "flat direction";
  r.parameters[3].value = 4.0;
  r.parameters[3].reason = "no tangential data";
  r.residual_count = 12;
  r.rms_relative_residual = 0.0123;
  r.rms_normal_um = 0.05;
  r.information_eigenvalues = {0.001, 0.1, 10.0, 1000.0};
  r.starts_run = 6;
  r.rounds = 3;
  PointPrediction p;
  p.measurement.amplitude_v = 100.0;
  p.measurement.frequency_hz = 40000.0;
  p.measurement.tip_normal_um = 1.5;
  p.predicted_normal_um = 1.4567891;
  r.predictions = {p};
  return r;
}

TEST(IdentificationJson, ValuesWithNullForUnidentifiedAndUnmeasured) {
  const std::string text = identification_json(small_result());
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j["parameters"].size(), 4u);
  EXPECT_EQ(j["parameters"][0]["key"], "c111_pa");
  EXPECT_DOUBLE_EQ(j["parameters"][0]["standard_error"].get<double>(), 1.2e11);
  EXPECT_EQ(j["parameters"][0]["significant"], true);
  EXPECT_TRUE(j["parameters"][2]["standard_error"].is_null());
  EXPECT_DOUBLE_EQ(j["parameters"][2]["value"].get<double>(), 3.0);  // the prior, kept
  EXPECT_EQ(j["parameters"][3]["reason"], "no tangential data");
  EXPECT_DOUBLE_EQ(j["rms_normal_um"].get<double>(), 0.05);
  EXPECT_TRUE(j["rms_tangential_um"].is_null());  // NaN: not measured
  EXPECT_EQ(j["amplitude_count"], 12);
  EXPECT_EQ(j["information_eigenvalues"].size(), 4u);
  EXPECT_EQ(j["starts"], 6);
  EXPECT_EQ(j["rounds"], 3);
}

TEST(IdentificationSummaryText, OneLinePerConstantAndTheResidual) {
  EXPECT_EQ(identification_summary_text(small_result()),
            "parameter          value          std. error   status\n"
            "c111_pa            -2.5e+12       1.2e+11      identified, significantly non-zero\n"
            "c1111_pa           +3e+14         4e+14        identified, NOT significantly non-zero\n"
            "e311_c_m2          +3             -            not identifiable, kept at prior: flat direction\n"
            "e3111_c_m2         +4             -            not identifiable, kept at prior: no tangential data\n"
            "RMS residual: 1.23 % (relative), normal 0.05 um over 12 amplitudes\n");
}

TEST(IdentificationFittedHeader, NamesTheInputsAndEachConstant) {
  EXPECT_EQ(identification_fitted_header("--config m.toml --amplitudes a.csv", small_result()),
            "# Written by `swum identify --config m.toml --amplitudes a.csv`.\n"
            "# Non-linear constants (paper Sec. 4, docs/model_spec.md §6.5):\n"
            "#   c111_pa = -2.5e+12 +- 1.2e+11 (fitted)\n"
            "#   c1111_pa = 3e+14 +- 4e+14 (fitted)\n"
            "#   e311_c_m2 = 3 (prior kept: not identifiable by these data)\n"
            "#   e3111_c_m2 = 4 (prior kept: not identifiable by these data)\n"
            "#   RMS relative residual 1.23 % over 12 amplitudes\n\n");
}

TEST(IdentificationResidualsCsv, MeasuredAndFittedPerAxisEmptyWhereAbsent) {
  EXPECT_EQ(identification_residuals_csv(small_result()),
            "amplitude_v,frequency_hz,tip_normal_um,fit_normal_um,tip_tangential_um,fit_tangential_um\n"
            "100,40000,1.5,1.45679,,\n");
}

}  // namespace
}  // namespace swum::host
