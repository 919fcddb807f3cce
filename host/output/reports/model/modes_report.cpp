#include "output/reports/model/modes_report.h"

#include <nlohmann/json.hpp>

#include "formats/number_format.h"

namespace swum::host {

std::string modes_json(const ModalConstants& c) {
  nlohmann::ordered_json j;
  j["f_l1_hz"] = c.f_l1_hz;
  j["f_b2_hz"] = c.f_b2_hz;
  j["f_l1_full_contact_hz"] = c.f_l1_full_contact_hz;
  j["length_mm"] = c.geometry.length_m * 1e3;
  j["half_height_mm"] = c.geometry.half_height_m * 1e3;
  j["substrate_thickness_mm"] = c.geometry.substrate_thickness_m * 1e3;
  j["piezo_thickness_mm"] = c.geometry.piezo_thickness_m * 1e3;
  j["wave_speed_m_s"] = c.wave_speed_m_s;
  j["m1_kg"] = c.m1_kg;
  j["k1_n_m"] = c.k1_n_m;
  j["c1_n_s_m"] = c.c1_n_s_m;
  j["m2_kg"] = c.m2_kg;
  j["k2_n_m"] = c.k2_n_m;
  j["c2_n_s_m"] = c.c2_n_s_m;
  j["alpha1"] = c.alpha1;
  j["beta1_per_m"] = c.beta1_per_m;
  j["beta2_per_m"] = c.beta2_per_m;
  j["g_n"] = c.g_n;
  j["g_t"] = c.g_t;
  j["g_tv"] = c.g_tv;
  j["phi_b_tip"] = c.phi_b_tip;
  j["static_q1_nm"] = c.static_q1_m * 1e9;
  for (std::size_t k = 0; k < c.a.size(); ++k) {
    j["a" + std::to_string(k)] = {{"group_a", c.a[k].group_a}, {"group_b", c.a[k].group_b}};
  }
  for (std::size_t k = 0; k < c.b.size(); ++k) {
    j["b" + std::to_string(k)] = {{"group_a", c.b[k].group_a}, {"group_b", c.b[k].group_b}};
  }
  return j.dump(2) + "\n";
}

std::string modes_text(const ModalConstants& c) {
  return format_numbers("L1 (longitudinal) natural frequency : %10.1f Hz\n", c.f_l1_hz) +
         format_numbers("B2 (bending) natural frequency      : %10.1f Hz\n", c.f_b2_hz) +
         format_numbers("L1 in full contact (k_e added)      : %10.1f Hz\n", c.f_l1_full_contact_hz) +
         format_numbers("stator length L / height 2hs        : %10.3f / %.3f mm\n", c.geometry.length_m * 1e3,
                        2 * c.geometry.half_height_m * 1e3) +
         format_numbers("M1, K1, C1 : %.6g kg, %.6g N/m, %.6g N s/m\n", c.m1_kg, c.k1_n_m, c.c1_n_s_m) +
         format_numbers("M2, K2, C2 : %.6g kg, %.6g N/m, %.6g N s/m\n", c.m2_kg, c.k2_n_m, c.c2_n_s_m) +
         format_numbers("gN, gT     : %.6g, %.6g\n", c.g_n, c.g_t);
}

}  // namespace swum::host
