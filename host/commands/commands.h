// Registration of the `swum` subcommands (one file each).
#pragma once

#include <CLI/CLI.hpp>

namespace swum::host {

void add_modes_command(CLI::App& app);         // modes_command.cpp
void add_simulate_command(CLI::App& app);      // simulate_command.cpp
void add_sweep_command(CLI::App& app);         // sweep_command.cpp
void add_validate_command(CLI::App& app);      // validate_command.cpp
void add_stator_command(CLI::App& app);        // stator_command.cpp
void add_admittance_command(CLI::App& app);    // admittance_command.cpp
void add_identify_command(CLI::App& app);      // identify_command.cpp
void add_pick_command(CLI::App& app);          // pick_command.cpp
void add_band_command(CLI::App& app);          // band_command.cpp
void add_size_command(CLI::App& app);          // size_command.cpp
void add_log_command(CLI::App& app);           // log_command.cpp
void add_synth_command(CLI::App& app);         // synth_command.cpp
void add_discrepancy_command(CLI::App& app);   // discrepancy_command.cpp
void add_calibrate_command(CLI::App& app);     // calibrate_command.cpp
void add_population_command(CLI::App& app);    // population_command.cpp
void add_control_command(CLI::App& app);       // control_command.cpp
void add_track_command(CLI::App& app);         // track_command.cpp
void add_track_report_command(CLI::App& app);  // track_report_command.cpp

}  // namespace swum::host
