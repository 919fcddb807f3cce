// `swum sweep --resume` (docs/host.md, "Killed, interrupted and resumed runs"): what a sweep's
// OUT.partial holds and may be continued from, checked against the sweep asked for.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "output/partial_file.h"
#include "output/sweep_table.h"

namespace swum::host {

/// What --resume keeps of OUT.partial: its rows (parsed) and their lines, header first.
struct SweepKept {
  std::vector<SweepRow> rows;
  std::vector<std::string> lines;

  /// Bytes of the header and the first `rows_kept` rows, with their newlines.
  std::size_t bytes(std::size_t rows_kept) const;
};

/// OUT.partial for --resume: the header of this kind of sweep, then rows at the first points of
/// `planned`, in order. The file has no room for the options themselves (a sweep file is plain
/// CSV), so a file of another grid is recognised by its points. Empty when the run was killed
/// before its header was written; throws CommandError "--resume: ..." otherwise.
SweepKept read_sweep_partial(const std::string& out_path, const std::string& header,
                             const std::vector<SweepRow>& planned);

/// A fresh run never overwrites the rows of an unfinished one (they may be an hour of
/// measurements): throws CommandError when OUT.partial holds a row.
void refuse_to_overwrite_sweep_partial(const std::string& out_path);

/// OUT.partial with the header and the first `rows_kept` rows of `kept`, ready for the next row.
PartialFile open_sweep_partial(const std::string& out_path, const std::string& header, const SweepKept& kept,
                               std::size_t rows_kept);

}  // namespace swum::host
