#include "output/sweep_resume.h"

#include <filesystem>
#include <system_error>

#include "commands/command_error.h"
#include "formats/number_format.h"

namespace swum::host {

std::size_t SweepKept::bytes(std::size_t rows_kept) const {
  std::size_t n = 0;
  for (std::size_t i = 0; i <= rows_kept; ++i) n += lines[i].size() + 1;
  return n;
}

SweepKept read_sweep_partial(const std::string& out_path, const std::string& header,
                             const std::vector<SweepRow>& planned) {
  SweepKept kept;
  kept.lines = read_partial_lines(out_path);
  const std::string partial = partial_path(out_path).string();
  if (kept.lines.empty()) return kept;  // killed before its header was written: start afresh
  if (kept.lines[0] + "\n" != header) {
    throw CommandError("--resume: " + partial + " does not start with this sweep's header (a " +
                       (header == format_sweep_header(kDeviceSweep) ? "model" : "device") +
                       " sweep, or not a sweep file?)");
  }
  std::string text;
  for (const std::string& line : kept.lines) text += line + "\n";
  kept.rows = parse_sweep_csv(text, partial);
  if (kept.rows.size() + 1 != kept.lines.size()) throw CommandError("--resume: " + partial + " has empty lines");
  if (kept.rows.size() > planned.size()) {
    throw CommandError("--resume: " + partial + " has " + std::to_string(kept.rows.size()) +
                       " rows, more than the points of this sweep (" + std::to_string(planned.size()) +
                       "): other --amplitude-v, --frequency-hz or --load?");
  }
  auto at = [](const SweepRow& r) {
    return format_number(r.amplitude_v) + "," + format_number(r.frequency_hz) + "," + format_number(r.load_n) + ",";
  };
  for (std::size_t i = 0; i < kept.rows.size(); ++i) {
    const std::string where = at(planned[i]);
    if (kept.lines[i + 1].compare(0, where.size(), where) != 0) {
      throw CommandError("--resume: row " + std::to_string(i + 1) + " of " + partial +
                         " is not at this sweep's point " + std::to_string(i + 1) +
                         " (amplitude_v,frequency_hz,load_n " + where.substr(0, where.size() - 1) +
                         "): other --amplitude-v, --frequency-hz or --load?");
    }
  }
  return kept;
}

void refuse_to_overwrite_sweep_partial(const std::string& out_path) {
  std::error_code ec;
  if (std::filesystem::exists(partial_path(out_path), ec) && read_partial_lines(out_path).size() > 1) {
    throw CommandError(partial_path(out_path).string() +
                       " holds an unfinished sweep: continue it with --resume, or delete it to start afresh");
  }
}

PartialFile open_sweep_partial(const std::string& out_path, const std::string& header, const SweepKept& kept,
                               std::size_t rows_kept) {
  if (rows_kept == 0) return PartialFile(out_path, header);
  return PartialFile::resume(out_path, kept.bytes(rows_kept));
}

}  // namespace swum::host
