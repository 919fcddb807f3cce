// Prints the model's steady state (swum::run_to_steady_state) for one operating point as JSON:
//   swum_emu_reference CONFIG V FREQUENCY_HZ [PHASE_DEG [LOAD_N]]
// The integration tests compare swum-emu's telemetry against it.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "analysis/steady_state/steady_state.h"
#include "formats/parameter_file.h"
#include "model/motor_model.h"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s CONFIG V FREQUENCY_HZ [PHASE_DEG [LOAD_N]]\n", argv[0]);
    return 2;
  }
  std::ifstream in(argv[1]);
  std::stringstream text;
  text << in.rdbuf();
  try {
    const swum::MotorModel model(swum::parse_motor_parameters(text.str(), argv[1]));
    swum::OperatingPoint point;
    point.amplitude_v = std::atof(argv[2]);
    point.frequency_hz = std::atof(argv[3]);
    if (argc > 4) point.phase_deg = std::atof(argv[4]);
    if (argc > 5) point.load_n = std::atof(argv[5]);
    const swum::SteadyStateResult r = swum::run_to_steady_state(model, point);
    std::printf("{\"ok\": %s, \"speed_mm_s\": %.6f, \"tip_normal_um\": %.6f, \"tip_tangential_um\": %.6f}\n",
                r.ok ? "true" : "false", r.speed_mm_s, r.tip_normal_um, r.tip_tangential_um);
    return r.ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
