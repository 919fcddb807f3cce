// Prints frames encoded by protocol/can_codec with the physical values they carry, one
// JSON object per line, for an independent decoder (dbc_canmatrix_check.py, python3-canmatrix).
#include <cstdio>
#include <map>
#include <string>

#include "can_codec.h"

namespace {
void print(const char* message, const swum::protocol::CanFrame& f, const std::map<std::string, double>& values) {
  std::printf("{\"message\": \"%s\", \"id\": %u, \"data\": \"", message, f.id);
  for (unsigned i = 0; i < f.dlc; ++i) std::printf("%02x", f.data[i]);
  std::printf("\", \"values\": {");
  bool first = true;
  for (const auto& [k, v] : values) {
    std::printf("%s\"%s\": %.9g", first ? "" : ", ", k.c_str(), v);
    first = false;
  }
  std::printf("}}\n");
}
}  // namespace

int main() {
  using namespace swum::protocol;
  const can::Ids ids = can::ids_for_node(1);
  can::CommandFrame c;
  c.mode = 1;
  c.alive = 11;
  c.frequency_hz = 40321.7;
  c.phase_deg = -123.4;
  c.amplitude_v = 345.5;
  const auto cf = can::encode_command(c, ids.command);
  print("Command", cf,
        {{"Mode", 1},
         {"AliveCounter", 11},
         {"Frequency", 40321.7},
         {"Phase", -123.4},
         {"Amplitude", 345.5},
         {"Crc", cf.data[7]}});
  can::AuxFrame a;
  a.alive = 4;
  a.load_n = -2.345;
  a.frequency_slew_hz_per_s = 250000;
  a.amplitude_slew_v_per_s = 5000;
  const auto af = can::encode_aux(a, ids.aux);
  print(
      "AuxCommand", af,
      {{"AliveCounter", 4}, {"Load", -2.345}, {"FrequencySlew", 250000}, {"AmplitudeSlew", 5000}, {"Crc", af.data[7]}});
  Telemetry t;
  t.state = AmpState::enabled;
  t.enable_line = true;
  t.at_setpoint = false;
  t.output.amplitude_v = 400;
  t.output.phase_deg = 90;
  t.output.frequency_hz = 40000.5;
  t.output.load_n = 0.75;
  t.applied_commands = 1000;
  t.speed_m_s = 0.198449;
  t.position_m = -0.0421;
  t.tip_normal_um = 2.946;
  t.tip_tangential_um = 1.063;
  t.stats.lateness_p50_ns = 4000;
  t.stats.lateness_p99_ns = 21000;
  t.stats.lateness_p999_ns = 70000;
  t.stats.lateness_max_ns = 180000;
  t.stats.overruns = 3;
  t.electrical = {0.2345, 0.1876, 34.56, -12.34, -1.23, 2.34, 12.34, -0.56};
  t.stator_temperature_c = 31.25;
  const RejectSnapshot r{Reason::bad_checksum, 1234};
  print("Status", can::encode_status(t, r, 17, ids.status),
        {{"State", 1},
         {"EnableLine", 1},
         {"DriveOn", 1},
         {"AtSetpoint", 0},
         {"FaultCode", 0},
         {"LastReject", 7},
         {"RejectCount", 1234 % 256},
         {"AppliedCount", 1000 % 256},
         {"StatusCounter", 17},
         {"StatorTemperature", 31.25}});
  print("Motion", can::encode_motion(t, ids.motion), {{"Speed", 198.449}, {"Position", -42.1}});
  print("Drive", can::encode_drive(t, ids.drive),
        {{"TipNormal", 2.946}, {"TipTangential", 1.063}, {"AmplitudeOut", 400}, {"PhaseOut", 90}});
  print("LoopStats", can::encode_loop_stats(t, ids.loop_stats),
        {{"LatenessP99", 21}, {"LatenessP999", 70}, {"LatenessMax", 180}, {"Overruns", 3}});
  print("Output", can::encode_output(t, ids.output),
        {{"FrequencyOut", 40000.5}, {"LoadOut", 0.75}, {"LatenessP50", 4}});
  t.sim_time_s = 3600.25;
  t.tick = 36002500;
  print("Clock", can::encode_clock(t, ids.clock), {{"SimTime", 3600.25}, {"Tick", 36002500}});
  print("ElectricalA", can::encode_electrical_a(t, ids.electrical_a),
        {{"CurrentA", 0.2345}, {"PhaseA", 34.56}, {"MotionalPhaseA", -1.23}, {"PowerA", 12.34}});
  print("ElectricalB", can::encode_electrical_b(t, ids.electrical_b),
        {{"CurrentB", 0.1876}, {"PhaseB", -12.34}, {"MotionalPhaseB", 2.34}, {"PowerB", -0.56}});
  print("Heartbeat", can::encode_heartbeat(ids.heartbeat), {{"NmtState", 5}});
  print("Sync", can::encode_sync(17), {{"SyncCounter", 17}});  // issue 13: lockstep over CAN
  return 0;
}
