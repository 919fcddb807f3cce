// swum: the host command-line tool. Each subcommand lives in its own file; main only
// wires them up and turns every failure into one line on stderr and an exit code.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/measurements/measurements.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/retired_options.h"
#include "installation.h"
#include "model/parameters.h"

int main(int argc, char** argv) {
  using namespace swum::host;
  CLI::App app{"swum: ultrasonic motor model, emulator client and operating-point tool"};
  app.require_subcommand(1);
  app.set_version_flag("--version", swum::installation::version_line("swum"));
  add_modes_command(app);
  add_simulate_command(app);
  add_sweep_command(app);
  add_validate_command(app);
  add_stator_command(app);
  add_admittance_command(app);
  add_identify_command(app);
  add_pick_command(app);
  add_band_command(app);
  add_size_command(app);
  add_log_command(app);
  add_synth_command(app);
  add_discrepancy_command(app);
  add_calibrate_command(app);
  add_population_command(app);
  add_control_command(app);
  add_track_command(app);
  add_track_report_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A retired spelling explains itself, whatever CLI11 stumbled on first (often the missing
    // new spelling of a required option).
    const std::vector<std::string> args(argv + 1, argv + argc);
    std::string program = "swum";
    for (const std::string& arg : args) {
      if (!app.get_subcommands([&arg](const CLI::App* sub) { return sub->get_name() == arg; }).empty()) {
        program += " " + arg;
        break;
      }
    }
    if (const std::string retired = retired_option_message(program, args); !retired.empty()) {
      std::fprintf(stderr, "%s\n", retired.c_str());
      return kExitUsage;
    }
    std::fprintf(stderr, "swum: error: %s (see swum --help)\n", e.what());
    return kExitUsage;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "swum: error: %s\n", e.what());
    return kExitUsage;
  } catch (const ReportedFailure& e) {
    return e.exit_code();
  } catch (const CommandError& e) {
    std::fprintf(stderr, "swum: error: %s\n", e.what());
    return e.exit_code();
  } catch (const swum::MeasurementError& e) {
    std::fprintf(stderr, "swum: error: %s\n", e.what());
    return kExitFailure;
  } catch (const swum::ParameterError& e) {
    std::fprintf(stderr, "swum: error: %s\n", e.what());
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "swum: error: %s\n", e.what());
    return kExitFailure;
  }
  return kExitOk;
}
