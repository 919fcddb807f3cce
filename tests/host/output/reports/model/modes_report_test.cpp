#include "output/reports/model/modes_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

ModalConstants constants() {
  ModalConstants c{};
  c.f_l1_hz = 40123.4;
  c.f_b2_hz = 39876.5;
  c.f_l1_full_contact_hz = 41000.0;
  c.geometry.length_m = 0.03;
  c.geometry.half_height_m = 0.002;
  c.m1_kg = 0.0125;
  c.k1_n_m = 7.9e8;
  c.c1_n_s_m = 12.5;
  c.m2_kg = 0.01;
  c.k2_n_m = 6.3e8;
  c.c2_n_s_m = 10.0;
  c.g_n = 1.5;
  c.g_t = -0.25;
  c.static_q1_m = 2e-9;
  return c;
}

TEST(ModesText, FrequenciesSizeAndModalConstants) {
  EXPECT_EQ(modes_text(constants()), "L1 (longitudinal) natural frequency :    40123.4 Hz\n"
                                     "B2 (bending) natural frequency      :    39876.5 Hz\n"
                                     "L1 in full contact (k_e added)      :    41000.0 Hz\n"
                                     "stator length L / height 2hs        :     30.000 / 4.000 mm\n"
                                     "M1, K1, C1 : 0.0125 kg, 7.9e+08 N/m, 12.5 N s/m\n"
                                     "M2, K2, C2 : 0.01 kg, 6.3e+08 N/m, 10 N s/m\n"
                                     "gN, gT     : 1.5, -0.25\n");
}

TEST(ModesJson, EveryConstantInMillimetresAndNanometresWhereNamed) {
  const std::string text = modes_json(constants());
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::ordered_json::parse(text);
  EXPECT_DOUBLE_EQ(j["f_l1_hz"].get<double>(), 40123.4);
  EXPECT_DOUBLE_EQ(j["length_mm"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(j["half_height_mm"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["k1_n_m"].get<double>(), 7.9e8);
  EXPECT_DOUBLE_EQ(j["g_t"].get<double>(), -0.25);
  EXPECT_NEAR(j["static_q1_nm"].get<double>(), 2.0, 1e-12);
  EXPECT_EQ(j.begin().key(), "f_l1_hz");
  EXPECT_TRUE(j.contains("a0"));
  EXPECT_TRUE(j["a0"].contains("group_a"));
}

}  // namespace
}  // namespace swum::host
