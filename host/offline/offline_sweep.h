// The offline counterpart of the live sweep: the model's steady speed at every
// (voltage, load, frequency) point, each from rest (run_to_steady_state), on all cores.
#pragma once

#include <vector>

#include "model/motor_model.h"
#include "output/sweep_table.h"

namespace swum::host {

struct OfflineGrid {
  std::vector<double> voltages;
  std::vector<double> frequencies_hz;
  std::vector<double> loads_n{0.0};
  double phase_deg = 90.0;
  int jobs = 0;  // 0 = all cores
};

// Throws std::invalid_argument naming the option (--vpp, --frequency, --load, --phase) of a
// value no sweep can use: voltages 0..10000 Vpp, frequencies 1000..200000 Hz, |load| <= 1000 N,
// phase -180..180 deg, every value finite.
void check_grid(const OfflineGrid& grid);

// Rows in (voltage, load, frequency) order; failed points have ok = false and a status.
std::vector<SweepRow> sweep_model(const MotorModel& model, const OfflineGrid& grid);

}  // namespace swum::host
