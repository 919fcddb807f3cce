#include "output/reports/model/simulation_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "formats/number_format.h"

namespace swum::host {
namespace {

double realtime_factor(const SteadyStateResult& r, double wall_s) { return wall_s > 0.0 ? r.sim_s / wall_s : 0.0; }

}  // namespace

std::string simulation_json(const OperatingPoint& point, const SteadyStateResult& r, double wall_s) {
  nlohmann::ordered_json j;
  j["amplitude_v"] = point.amplitude_v;
  j["frequency_hz"] = point.frequency_hz;
  j["load_n"] = point.load_n;
  j["phase_deg"] = point.phase_deg;
  j["steady"] = r.ok;
  if (!r.ok) j["note"] = r.failure;
  j["speed_mm_s"] = r.speed_mm_s;
  j["tip_normal_um"] = r.tip_normal_um;
  j["tip_tangential_um"] = r.tip_tangential_um;
  j["contact_fraction"] = r.contact_fraction;
  j["mean_normal_force_n"] = r.mean_normal_force_n;
  j["mean_friction_force_n"] = r.mean_friction_force_n;
  j["sim_s"] = r.sim_s;
  j["steps"] = r.steps;
  j["wall_s"] = wall_s;
  j["realtime_factor"] = realtime_factor(r, wall_s);
  return j.dump(2) + "\n";
}

std::string simulation_text(const OperatingPoint& point, const SteadyStateResult& r, double wall_s) {
  std::string out = format_numbers("operating point : %g V, %g Hz, load %g N, phase %g deg\n", point.amplitude_v,
                                   point.frequency_hz, point.load_n, point.phase_deg);
  if (!r.ok) out += "note            : not settled (" + r.failure + ")\n";
  out += format_numbers("mover speed     : %.3f mm/s\n", r.speed_mm_s) +
         format_numbers("tip amplitudes  : normal %.4f um, tangential %.4f um\n", r.tip_normal_um,
                        r.tip_tangential_um) +
         format_numbers("contact fraction: %.3f\n", r.contact_fraction) +
         format_numbers("simulated       : %.4f s in %.3f s wall (%.1fx real time)\n", r.sim_s, wall_s,
                        realtime_factor(r, wall_s));
  return out;
}

std::string simulation_trace_header() {
  return "time_s,q1_m,q1_dot_m_s,q2_m,q2_dot_m_s,tip_normal_um,tip_tangential_um,"
         "normal_force_n,friction_force_n,mover_position_m,mover_velocity_m_s\n";
}

void append_simulation_trace_row(std::string& csv, const TraceSample& s) {
  std::string line;
  line = printf_string("%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.9g,%.9g\n", s.time_s, s.q1_m, s.q1_dot_m_s,
                       s.q2_m, s.q2_dot_m_s, s.tip_normal_um, s.tip_tangential_um, s.normal_force_n, s.friction_force_n,
                       s.mover_position_m, s.mover_velocity_m_s);
  csv += line;
}

}  // namespace swum::host
