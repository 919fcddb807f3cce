// Parsing of the command-line value forms shared by several subcommands:
// comma lists ("100,250,400") and ranges ("39000:41000:100").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace swum::host {

/// Parses a finite number; throws std::invalid_argument naming `what` and the text.
double parse_finite_number(std::string_view text, std::string_view what);

/// "A,B,C" -> {A,B,C} (split as formats/name_list.h: blanks around an entry dropped); every
/// entry finite, none empty. `what` names the option in errors.
std::vector<double> parse_number_list(std::string_view text, std::string_view what);

/// "START:STOP:STEP" -> START, START+STEP, ... up to STOP inclusive (within STEP/1e6).
/// A plain number is a single point. STEP must be > 0 and STOP >= START; at most
/// `max_points` points so a typo cannot allocate gigabytes.
std::vector<double> parse_range_or_value(std::string_view text, std::string_view what, std::size_t max_points = 100000);

}  // namespace swum::host
