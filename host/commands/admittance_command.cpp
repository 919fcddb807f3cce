// `swum admittance [--config F] [--amplitude-v LIST] [--frequency-hz START:STOP:STEP] [--driven-phase a|b]
// [--mounting free|assembled]`: one phase's admittance Y(f) as an impedance analyser measures it
// (the other phase shorted), per drive level, and the Butterworth-Van Dyke circuit fitted to it
// next to the analytic one from the modal constants (docs/host.md, docs/model.md "Equivalent
// circuit").
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/admittance/admittance_measurement.h"
#include "analysis/admittance/circuit_fit.h"
#include "analysis/admittance/equivalent_circuit.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/number_format.h"
#include "offline/motor_config.h"
#include "output/reports/model/admittance_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct AdmittanceOptions {
  std::string config_path;
  std::string amplitude_v_list = "1";
  std::string frequency_range = "38000:41000:50";
  std::string phase = "a";
  std::string mounting = "free";
  std::string csv_path;
  bool json = false;
  std::string plot_dir;
};

constexpr double kMaxAmplitudeV = 1000.0;

void run_admittance(const AdmittanceOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  for (double v : voltages) {
    if (!(v > 0.0 && v <= kMaxAmplitudeV))
      throw std::invalid_argument("--amplitude-v: " + format_number(v, "%g") + " outside (0, 1000] V");
  }
  const std::vector<double> frequencies = parse_range_or_value(o.frequency_range, "--frequency-hz", 10000);
  if (frequencies.size() < kCircuitFitMinimumPoints)
    throw std::invalid_argument("--frequency-hz: " + std::to_string(frequencies.size()) +
                                " points; the circuit fit needs at least " + std::to_string(kCircuitFitMinimumPoints));
  for (double f : frequencies) {
    if (f < 1000.0 || f > 200000.0) throw std::invalid_argument("--frequency-hz: must be within 1000..200000 Hz");
  }
  if (o.phase != "a" && o.phase != "b") throw std::invalid_argument("--driven-phase: '" + o.phase + "' is not a or b");
  if (o.mounting != "free" && o.mounting != "assembled")
    throw std::invalid_argument("--mounting: '" + o.mounting + "' is not free or assembled");

  const MotorParameters parameters = load_motor_parameters(o.config_path);
  AdmittanceReport report;
  report.source = o.config_path;
  report.phase = o.phase == "a" ? DrivenPhase::a : DrivenPhase::b;
  report.mounting = o.mounting == "free" ? Mounting::free : Mounting::assembled;
  const MotorModel model(mounted_parameters(parameters, report.mounting));
  report.analytic = analytic_equivalent_circuit(model, report.phase, report.mounting);
  CircuitFitOptions fit_options;
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    fit_options.reference_inductance_h[i] = report.analytic.branches[i].inductance_h;
  }
  for (double v : voltages) {
    AdmittanceSweepOptions sweep;
    sweep.phase = report.phase;
    sweep.mounting = report.mounting;
    sweep.amplitude_v = v;
    sweep.frequencies_hz = frequencies;
    AdmittanceLevel level;
    level.amplitude_v = v;
    level.points = measure_admittance(parameters, sweep);
    level.fit = fit_equivalent_circuit(level.points, fit_options);
    report.levels.push_back(std::move(level));
  }
  std::fputs((o.json ? admittance_json(report) : admittance_text(report)).c_str(), stdout);
  if (!o.csv_path.empty()) write_text_file_atomically(o.csv_path, admittance_csv(report));
  if (!o.plot_dir.empty()) {
    std::error_code error;
    std::filesystem::create_directories(o.plot_dir, error);
    if (error) throw CommandError("cannot create " + o.plot_dir + ": " + error.message());
    write_admittance_plots(report, o.plot_dir);
  }
  // Diverged points or a failed fit: what was measured is printed and written (diverged = 1),
  // and the run says which level went wrong and fails.
  if (const std::string problem = admittance_problem(report); !problem.empty()) {
    const bool diverged = problem.find("diverged") != std::string::npos;
    throw CommandError(problem, diverged ? kExitDiverged : kExitFailure);
  }
}

}  // namespace

void add_admittance_command(CLI::App& app) {
  auto o = std::make_shared<AdmittanceOptions>();
  CLI::App* sub = app.add_subcommand(
      "admittance", "A phase's admittance Y(f) as on an impedance analyser and its fitted BVD equivalent circuit");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "drive levels: terminal voltage amplitudes of the driven phase, comma list (V, zero-to-peak)")
      ->capture_default_str();
  sub->add_option("--frequency-hz", o->frequency_range,
                  "START:STOP:STEP (Hz), at least " + std::to_string(kCircuitFitMinimumPoints) +
                      " points, swept from STOP down to START per level")
      ->capture_default_str();
  sub->add_option("--driven-phase", o->phase, "driven phase, a or b (the other is shorted, 0 V)")
      ->capture_default_str();
  sub->add_option("--mounting", o->mounting,
                  "free (the stator alone: no preload, no contact) or assembled (the motor as configured)")
      ->capture_default_str();
  sub->add_option("--csv", o->csv_path,
                  "write amplitude_v,frequency_hz,magnitude_siemens,phase_deg,conductance_siemens,susceptance_siemens,"
                  "current_a,diverged");
  sub->add_flag("--json", o->json, "print one JSON object (analytic circuit, per level the fit and Y(f))");
  sub->add_option("--plot-dir", o->plot_dir,
                  "write admittance_magnitude.png, admittance_phase.png, admittance_circle.png here");
  sub->callback([o] { run_admittance(*o); });
}

}  // namespace swum::host
