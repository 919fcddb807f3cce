// Whole-file reads and atomic whole-file writes: a reader never sees half a file, and a
// failed run never leaves a truncated output behind.
#pragma once

#include <filesystem>
#include <string>

namespace swum::host {

/// Reads a whole file; throws CommandError "cannot read PATH: <errno text>".
std::string read_text_file(const std::filesystem::path& path);

/// Writes to PATH.tmp then renames over PATH; throws CommandError with errno text.
void write_text_file_atomically(const std::filesystem::path& path, const std::string& contents);

}  // namespace swum::host
