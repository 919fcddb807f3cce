// swum-emu's CANopen profile (CanopenProfile, in lockstep) on stdin/stdout, so that the bench's
// CANopen master (bench/swum_bench/canopen_link.py, written apart from this C++) can be tested on
// a host without SocketCAN: tests/bench/test_canopen_link_profile.py drives it.
//
//   canopen_stdio_slave NODE
//
// Each input line is one of:
//   III#HEX                 a frame (cansend text), given to the profile as CanTransport gives it:
//                           a SYNC (0x080) in lockstep is send_telemetry() of the snapshot below
//   telemetry KEY=N ...     the snapshot the next SYNC samples: statusword, error_code,
//                           speed_um_s, position_um, frequency_mhz, amplitude_mv
//   request                 prints the drive request the profile publishes (DriveRequest)
// The frames the profile sends answer as III#HEX lines, then a line "." ends the answer. The
// power-up boot-up is sent before the first input, answered the same way.
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include "core/lockstep_clock.h"
#include "transports/canopen_profile.h"

namespace {

using swum::emu::CanNodePort;

class PrintingPort final : public CanNodePort {
 public:
  void send(const swum::io::CanFrame& frame) override {
    std::printf("%s\n", swum::protocol::to_cansend(frame).c_str());
  }
  swum::emu::Reason submit(swum::emu::Command /*command*/) override { return swum::emu::Reason::none; }
};

// One "KEY=N" of a telemetry line into the snapshot; false for a key it does not know.
bool set_telemetry(swum::emu::Telemetry& t, const std::string& key, double value) {
  if (key == "statusword") t.cia402.statusword = static_cast<std::uint16_t>(value);
  else if (key == "error_code") t.cia402.error_code = static_cast<std::uint16_t>(value);
  else if (key == "speed_um_s") t.speed_m_s = value * 1e-6;
  else if (key == "position_um") t.position_m = value * 1e-6;
  else if (key == "frequency_mhz") t.output.frequency_hz = value * 1e-3;
  else if (key == "amplitude_mv") t.cia402.terminal_amplitude_v = value * 1e-3;
  else return false;
  return true;
}

void print_request(const swum::emu::DriveRequest& r) {
  std::printf("request controlword=%u mode=%d frequency_mhz=%u amplitude_mv=%u phase_cdeg=%d target_velocity_um_s=%d "
              "fault_reset_edges=%u frequency_slew_hz_per_s=%u amplitude_slew_v_per_s=%u\n",
              static_cast<unsigned>(r.controlword), static_cast<int>(r.mode), static_cast<unsigned>(r.frequency_mhz),
              static_cast<unsigned>(r.amplitude_mv), static_cast<int>(r.phase_cdeg),
              static_cast<int>(r.target_velocity_um_s), static_cast<unsigned>(r.fault_reset_edges),
              static_cast<unsigned>(r.frequency_slew_hz_per_s), static_cast<unsigned>(r.amplitude_slew_v_per_s));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: canopen_stdio_slave NODE\n");
    return 2;
  }
  swum::emu::SharedState shared;
  swum::emu::LockstepClock clock;
  shared.lockstep = &clock;  // SYNC is the clock: synchronous PDOs act and are sampled at it
  swum::emu::CanopenProfileConfig config;
  config.node = static_cast<std::uint8_t>(std::atoi(argv[1]));
  config.heartbeat_ms = 0;  // no heartbeat frames between the answers
  swum::emu::CanopenProfile profile(config, shared);
  PrintingPort port;
  swum::emu::Telemetry telemetry;
  std::int64_t now_ns = 1'000'000'000;  // wall time for the SDO timeouts, 1 ms per line
  profile.send_periodic(now_ns, port);
  std::printf(".\n");
  std::fflush(stdout);
  std::string line;
  while (std::getline(std::cin, line)) {
    now_ns += 1'000'000;
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first == "telemetry") {
      std::string pair;
      while (words >> pair) {
        const auto eq = pair.find('=');
        if (eq == std::string::npos || !set_telemetry(telemetry, pair.substr(0, eq), std::atof(pair.c_str() + eq + 1)))
          std::printf("error unknown telemetry %s\n", pair.c_str());
      }
    } else if (first == "request") {
      print_request(shared.drive_request.load());
    } else {
      swum::io::CanFrame frame;
      if (const std::string error = swum::protocol::parse_cansend(first, frame); !error.empty()) {
        std::printf("error %s\n", error.c_str());
      } else if (frame.id == 0x080 && !frame.extended) {
        profile.send_telemetry(telemetry, swum::emu::RejectSnapshot{}, port);
      } else {
        profile.receive(frame, swum::emu::CanRxTime{now_ns, now_ns}, port);
        profile.send_periodic(now_ns, port);  // an SDO abort of a timeout, as the transmit thread would
      }
    }
    std::printf(".\n");
    std::fflush(stdout);
  }
  return 0;
}
