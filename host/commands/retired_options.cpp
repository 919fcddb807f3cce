#include "commands/retired_options.h"

#include <array>

namespace swum::host {

namespace {

// One row per retired spelling: old, new (empty: removed, nothing replaces it), why.
constexpr std::array kRetired{
    RetiredOption{"--frequency", "--frequency-hz", "every frequency option carries its unit"},
    RetiredOption{"--duration", "--duration-s", "every duration option carries its unit"},
    RetiredOption{"--threads", "--jobs", "one name for worker threads in every command"},
    RetiredOption{"--plots", "--plot-dir", "--plot names one PNG file, --plot-dir a directory of plots"},
    RetiredOption{"--phase", "--drive-phase-deg", "the drive phase (B ahead of A), unlike track's motional phase"},
    RetiredOption{"--phase", "--driven-phase", "which phase the analyser drives, a or b; the other is shorted",
                  "swum admittance"},
    RetiredOption{"--phase-deg", "--motional-phase-deg", "track's motional-phase set-point, not the drive phase"},
    RetiredOption{"--frequency-slew", "--frequency-slew-hz-per-s", "every slew limit carries its unit"},
    RetiredOption{"--window-ms", "--dwell-ms", "the sampling window per point, as swum sweep and pick name it"},
    RetiredOption{"--min-hz", "--min-frequency-hz", "frequency bounds named alike in swum and swum-emu"},
    RetiredOption{"--max-hz", "--max-frequency-hz", "frequency bounds named alike in swum and swum-emu"},
    RetiredOption{"--phase-gain", "--phase-gain-hz-per-deg", "a gain carries its unit"},
    RetiredOption{"--vpp", "--amplitude-v", "a voltage is the terminal amplitude of one phase, in V"},
    RetiredOption{"--max-vpp", "--max-amplitude-v", "a voltage is the terminal amplitude of one phase, in V"},
    RetiredOption{"--vpp-slew", "--amplitude-slew-v-per-s", "the terminal amplitude's slew limit, in V/s"},
    RetiredOption{"--ramp-vpp-per-s", "--amplitude-slew-v-per-s", "the terminal amplitude's slew limit, in V/s"},
    RetiredOption{"--voltage-convention", "", "the drive's objects are terminal amplitudes; nothing to convert"},
};

bool spells(std::string_view arg, std::string_view option) {
  return arg == option || (arg.size() > option.size() && arg.starts_with(option) && arg[option.size()] == '=');
}

}  // namespace

std::span<const RetiredOption> retired_options() { return kRetired; }

const RetiredOption* find_retired_option(std::span<const std::string> args, std::span<const RetiredOption> table,
                                         std::string_view program) {
  for (const std::string& arg : args) {
    if (arg == "--") return nullptr;  // what follows is not an option
    const RetiredOption* general = nullptr;
    for (const RetiredOption& retired : table) {
      if (!spells(arg, retired.old_spelling)) continue;
      if (!retired.program.empty() && retired.program == program) return &retired;
      if (retired.program.empty() && general == nullptr) general = &retired;
    }
    if (general != nullptr) return general;
  }
  return nullptr;
}

std::string retired_option_message(std::string_view program, std::span<const std::string> args,
                                   std::span<const RetiredOption> table) {
  const RetiredOption* retired = find_retired_option(args, table, program);
  if (retired == nullptr) return {};
  const std::string what = retired->new_spelling.empty() ? " was removed"
                                                         : " was renamed " + std::string(retired->new_spelling);
  return std::string(program) + ": " + std::string(retired->old_spelling) + what + " (" + std::string(retired->why) +
         ")";
}

}  // namespace swum::host
