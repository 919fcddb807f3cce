// What `swum band` prints and writes (docs/host.md): the rows as CSV (--out), and the band
// with its rows as JSON (--json) or as a few lines of text.
#pragma once

#include <string>
#include <vector>

#include "analysis/operating_point/operating_band.h"

namespace swum::host {

/// Header and one row per (voltage, load, temperature rise); cells of an undecided row are
/// empty, commas in its reason written as ';'.
std::string band_csv(const std::vector<BandRow>& rows);

/// As `swum pick --json`: numbers as JSON numbers, null where undecided (pretty, ordered
/// keys, '\n' at the end). `margin_hz`: the --margin-hz asked for.
std::string band_json(const std::vector<BandRow>& rows, const BandSummary& s, double margin_hz);

/// The band, the peak range, the count of rows and each undecided row's reason;
/// `out_path`: where the rows went (none when empty).
std::string band_text(const std::vector<BandRow>& rows, const BandSummary& s, double margin_hz,
                      const std::string& out_path);

}  // namespace swum::host
