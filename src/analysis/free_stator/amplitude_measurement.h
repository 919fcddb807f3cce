// One measured (or synthesised) free-stator operating point: the data of paper Figs. 7-8 and
// the input of the identification (model_spec §6.5). Either amplitude may be missing.
#pragma once

#include <optional>

namespace swum {

struct AmplitudeMeasurement {
  double amplitude_v = 0.0;  // as DriveInput::amplitude_v
  double frequency_hz = 0.0;
  std::optional<double> tip_normal_um;      // U, amplitude of u_tip (um)
  std::optional<double> tip_tangential_um;  // W, amplitude of w_tip = phiB(L) q2 (um, eq. 30)
  int source_line = 0;                      // line in the source file (0 = none); for messages only
};

}  // namespace swum
