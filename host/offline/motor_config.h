// Loads a motor parameter file (TOML) from disk: the file I/O the pure model library
// leaves to its callers.
#pragma once

#include <filesystem>

#include "model/parameters.h"

namespace swum::host {

/// Reads and validates PATH; throws CommandError (unreadable) or swum::ParameterError
/// (bad content, naming the file, key and allowed range).
MotorParameters load_motor_parameters(const std::filesystem::path& path);

}  // namespace swum::host
