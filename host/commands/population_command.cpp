// `swum population --config F --spreads S --motors N --amplitude-v LIST --out motors.csv`: a Monte-Carlo
// study over manufacturing tolerances. Each motor's parameters are drawn from the study's
// counter-based stream, its operating frequency per voltage picked as `swum pick --config`
// picks it; rows go to motors.csv(.partial) as motors complete, then the distribution per
// voltage and the oscillator range for a yield (docs/population.md). On all cores, and over the
// ranks of `mpirun -np K swum population ...` with the same files.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "analysis/studies/population.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/spread_file.h"
#include "model/simulation/batch_simulator.h"
#include "offline/motor_config.h"
#include "offline/offline_sweep.h"
#include "offline/population_study.h"
#include "offline/rank_world.h"
#include "output/partial_file.h"
#include "output/progress_bar.h"
#include "output/reports/operating_point/population_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct PopulationOptions {
  std::string config_path;
  std::string spreads_path;
  std::uint64_t motors = 0;
  std::uint64_t seed = 1;
  std::string amplitude_v_list;
  std::string frequency_range = kDefaultFrequencyGrid;  // the operating point's defaults, as swum pick
  double load_n = 0.0;
  double margin_hz = kDefaultMarginHz;
  double yield = 0.95;
  unsigned jobs = 0;
  std::string out_path;
  std::string summary_path;
  bool json = false;
};

constexpr std::uint64_t kMaxMotors = 1000000;  // the summary keeps every motor in memory (~0.5 kB each)

// Everything the study needs, read and checked before any motor runs (the same on every rank).
PopulationStudy prepare(const PopulationOptions& o) {
  if (o.motors < 1 || o.motors > kMaxMotors) throw std::invalid_argument("--motors: must be within 1..1000000");
  if (!(o.yield > 0.0 && o.yield <= 1.0)) throw std::invalid_argument("--yield: must be within (0, 1]");
  if (!(o.margin_hz >= 0.0 && o.margin_hz <= 10000.0)) {
    throw std::invalid_argument("--margin-hz: must be within 0..10000");
  }
  if (o.jobs > 1024) throw std::invalid_argument("--jobs: must be within 0..1024");
  PopulationStudy study;
  study.voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  study.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency-hz");
  study.load_n = o.load_n;
  check_grid(OfflineGrid{study.voltages, study.frequencies_hz, {study.load_n}});
  for (std::size_t a = 0; a < study.voltages.size(); ++a) {
    for (std::size_t b = 0; b < a; ++b) {
      // The pick matches a curve's voltage within 1e-6 relative (model_pick): closer ones are one.
      if (std::abs(study.voltages[a] - study.voltages[b]) <=
          1e-6 * std::max(std::abs(study.voltages[a]), std::abs(study.voltages[b]))) {
        throw std::invalid_argument("--amplitude-v: a voltage is given twice");
      }
    }
  }
  study.pick.min_margin_hz = o.margin_hz;
  study.seed = o.seed;
  study.motors = o.motors;
  study.nominal = load_motor_parameters(o.config_path);
  study.spreads = parse_parameter_spreads(read_text_file(o.spreads_path), o.spreads_path, study.nominal);
  return study;
}

int exit_code_of(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const CommandError& e) {
    return e.exit_code();
  } catch (const std::invalid_argument&) {
    return kExitUsage;
  } catch (...) {
    return kExitFailure;
  }
}

// A small code of the SIMD target the lanes run on here (BatchSimulator::simd_target): AVX2 and
// AVX-512 fuse multiply-adds, SSE4 and below do not, so ranks on unlike CPUs would differ in the
// last digits of their motors.
int simd_target_code() {
  int code = 0;
  for (const char* c = BatchSimulator::simd_target(); *c != '\0'; ++c) code = (code * 131 + *c) & 0x3fffffff;
  return code;
}

void run_population(const PopulationOptions& o) {
  RankWorld world;
  // Every rank takes part (a collective), before anything that can fail on one rank only.
  const bool same_simd_target = world.from_root(simd_target_code()) == simd_target_code();
  // Setup: every rank reads and checks the same inputs; rank 0 also opens the output. A
  // failure anywhere ends every rank with the same status, reported once.
  std::optional<PopulationStudy> study;
  std::unique_ptr<PartialFile> file;
  std::exception_ptr setup_error;
  try {
    if (!same_simd_target) {
      throw CommandError("rank " + std::to_string(world.rank()) + " runs its SIMD lanes on " +
                             BatchSimulator::simd_target() +
                             ", rank 0 on another instruction set: results would differ in the last digits; run the "
                             "ranks on like CPUs (docs/population.md)",
                         kExitFailure);
    }
    study = prepare(o);
    if (world.root()) file = std::make_unique<PartialFile>(o.out_path, population_csv_header(*study));
  } catch (...) {
    setup_error = std::current_exception();
  }
  const int setup_code = world.max_over_ranks(setup_error ? exit_code_of(setup_error) : 0);
  if (setup_code != 0) {
    const bool root_failed = world.from_root(setup_error ? 1 : 0) != 0;
    if (setup_error && (world.root() || !root_failed)) std::rethrow_exception(setup_error);
    throw ReportedFailure(setup_code);
  }

  std::vector<MotorOutcome> outcomes(world.root() ? study->motors : 0);
  try {
    std::optional<InOrderRows> rows;
    if (world.root()) rows.emplace(*file, 0);
    ProgressBar progress("motors", world.root() ? study->motors : 0);
    world.for_each(
        study->motors, world.threads(o.jobs),
        [&](std::size_t i) { return encode_motor_outcome(run_population_motor(*study, i)); },
        [&](std::size_t i, std::string bytes) {
          MotorOutcome outcome = decode_motor_outcome(bytes);
          rows->complete(i, population_csv_row(*study, outcome));
          outcomes[i] = std::move(outcome);
          progress.advance();
        });
  } catch (const std::exception& e) {
    if (world.size() > 1) {
      // The other ranks would wait for this one: end the job.
      std::fprintf(stderr, "swum: error: rank %d: %s\n", world.rank(), e.what());
      world.abort(exit_code_of(std::current_exception()));
    }
    throw;
  }
  if (!world.root()) return;
  file->commit();
  const PopulationSummaryInputs inputs{o.config_path, o.spreads_path, o.frequency_range, o.yield};
  const std::string json = population_summary_json(*study, outcomes, inputs);
  if (!o.summary_path.empty()) write_text_file_atomically(o.summary_path, json);
  std::fputs(o.json ? json.c_str() : population_summary_text(*study, outcomes, inputs).c_str(), stdout);
  std::fflush(stdout);
  if (!population_yield_reached(outcomes, o.yield)) {
    throw CommandError("no oscillator range reaches the yield: too many motors have no operating frequency at "
                       "some voltage (see the note column of " +
                       o.out_path + ")");
  }
}

}  // namespace

void add_population_command(CLI::App& app) {
  auto o = std::make_shared<PopulationOptions>();
  CLI::App* sub = app.add_subcommand(
      "population", "Monte-Carlo motor population: operating frequency and speed per voltage over tolerances");
  add_config_option(*sub, o->config_path, "nominal motor parameter file");
  sub->add_option("--spreads", o->spreads_path, "spreads file: which parameters vary and how (TOML)")->required();
  sub->add_option("--motors", o->motors, "motors to draw (1..1000000)")->required();
  sub->add_option("--seed", o->seed, "study seed: motor i's parameters depend on (seed, i) only")
      ->check(CLI::NonNegativeNumber)  // CLI11 reads "-1" into an unsigned as 2^64 - 1
      ->capture_default_str();
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub->add_option("--frequency-hz", o->frequency_range, "START:STOP:STEP swept per motor and voltage (Hz)")
      ->capture_default_str();
  sub->add_option("--load", o->load_n, "load (N)")->capture_default_str();
  sub->add_option("--margin-hz", o->margin_hz, "minimum margin above the peak (Hz), as swum pick")
      ->capture_default_str();
  sub->add_option("--yield", o->yield, "share of motors the oscillator range must cover, (0, 1]")
      ->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads per process (0: all cores, shared by the ranks on a machine)")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "per-motor CSV (rows in OUT.partial until the study completes)")->required();
  sub->add_option("--summary", o->summary_path, "also write the summary JSON here");
  sub->add_flag("--json", o->json, "summary as JSON on stdout");
  sub->callback([o] { run_population(*o); });
}

}  // namespace swum::host
