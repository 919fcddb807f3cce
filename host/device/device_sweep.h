// Frequency sweeps and steady-speed measurements on a live device (host/device/device.h): the
// procedure of docs/host.md ("Live sweep"). Pure protocol-independent logic, so a fake device
// obeying the same contract can test it.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "device/device.h"
#include "output/sweep_table.h"

namespace swum::host {

struct DeviceSweepPlan {
  std::vector<double> voltages;        // V; each swept separately
  std::vector<double> frequencies_hz;  // any order: swept from the highest down
  std::vector<double> loads_n{0.0};
  double phase_deg = 90.0;
  double settle_s = 0.05;                  // after the frequency is reached, before sampling (device time)
  double dwell_s = 0.05;                   // sampling window per point (device time)
  double amplitude_slew_v_per_s = 2000.0;  // amplitude slew limit set on the device for the voltage ramps
  double keep_alive_s = 0.02;              // at most this long (host and device time) between commands
  double poll_interval_s = 0.001;          // host time between telemetry reads (a fast loopback device
                                           // answers in ~0.1 ms: no need to poll it flat out)
};

// Throws std::invalid_argument naming the option of anything the sweep cannot do (empty lists,
// unbounded settle/dwell, a ramp the protocols cannot carry). sweep_device calls it first;
// commands call it before they open the device or touch any file.
void check_plan(const DeviceSweepPlan& plan);

// Called after each point (progress, the row written to the file).
using PointDone = std::function<void(const SweepRow&)>;

// Where a resumed sweep starts (`swum sweep --resume`, docs/host.md): the first `curves_done`
// (load, voltage) curves are measured already; the next one is measured whole from its top
// frequency, since a curve is one continuous downward pass (a curve cut short is measured
// again: its points depend on the way down, hysteresis).
struct DeviceSweepStart {
  std::size_t curves_done = 0;
  int first_sweep_id = 0;      // sweep ids go on from here ...
  double time_offset_s = 0.0;  // ... and time_s from here (the pause between runs not counted)
};

// The plan's points in the order they are measured (and written): for each load, each
// voltage, the frequencies from the highest down. One curve = one (load, voltage).
std::vector<SweepRow> device_sweep_points(const DeviceSweepPlan& plan);

// How much of `finished` (rows of an interrupted sweep of `plan`, in order) a resumed sweep
// keeps: the whole curves; `kept` is set to their number of rows.
DeviceSweepStart device_sweep_start(const DeviceSweepPlan& plan, const std::vector<SweepRow>& finished,
                                    std::size_t& kept);

// Runs the plan (from `start`: the curves before it are skipped); appends a row to `rows` per
// point; the drive is off (disabled) when it returns or throws. Throws DeviceError on a device
// problem, CommandError(kExitInterrupted) on Ctrl-C; `rows` holds what was measured until then.
void sweep_device(Device& device, const DeviceSweepPlan& plan, std::vector<SweepRow>& rows,
                  const PointDone& point_done = {}, const DeviceSweepStart& start = {});

}  // namespace swum::host
