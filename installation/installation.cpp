#include "installation.h"

#include <cstdlib>
#include <stdexcept>
#include <system_error>

// Set by installation/CMakeLists.txt for this file only, so that a new version or commit recompiles
// this one file.
#ifndef SWUM_VERSION
#error "SWUM_VERSION is not defined (installation/CMakeLists.txt)"
#endif

namespace swum::installation {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kDefaultConfig = "li2019.toml";

bool holds_default_config(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / kDefaultConfig, ec);
}

// Is `path` inside `dir` (both absolute, lexically normal)?
bool is_inside(const fs::path& path, const fs::path& dir) {
  const fs::path rel = path.lexically_relative(dir);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

std::string_view version() { return SWUM_VERSION; }

std::string version_line(std::string_view program) {
  std::string line = std::string(program) + " " + std::string(version());
  const std::string_view git = SWUM_GIT_DESCRIBE;
  if (!git.empty()) line += " (git " + std::string(git) + ")";
  return line;
}

std::optional<fs::path> find_data_dir(const fs::path& exe, const char* env, std::string& tried) {
  tried.clear();
  if (env != nullptr && *env != '\0') {
    // An explicit choice is the only one: a wrong $SWUM_DATA_DIR is an error, not a fallback.
    const fs::path dir(env);
    if (holds_default_config(dir)) return dir;
    tried = "$SWUM_DATA_DIR=" + dir.string() + " (no " + std::string(kDefaultConfig) + " there)";
    return std::nullopt;
  }
  // Relocatable: PREFIX/bin/swum finds PREFIX/share/swum-hil, for /usr, /usr/local or an
  // unpacked package alike.
  const fs::path installed = (exe.parent_path() / SWUM_RELATIVE_DATA_DIR).lexically_normal();
  if (holds_default_config(installed)) return installed;
  tried = installed.string();
  // A build of this checkout (the executable under its build folder) reads the checkout's
  // config/; an installed binary never does, even when the checkout is still there.
  // Both sides with symbolic links resolved: /proc/self/exe is, a checkout reached through a link
  // is not.
  std::error_code ec;
  const fs::path build_dir = fs::weakly_canonical(SWUM_BUILD_DIR, ec).lexically_normal();
  const fs::path source_data = fs::weakly_canonical(SWUM_SOURCE_DATA_DIR, ec).lexically_normal();
  if (is_inside(fs::weakly_canonical(exe, ec).lexically_normal(), build_dir)) {
    if (holds_default_config(source_data)) return source_data;
    tried += ", " + source_data.string();
  }
  return std::nullopt;
}

fs::path data_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::string tried;
  if (auto dir = find_data_dir(ec ? fs::path() : exe, std::getenv("SWUM_DATA_DIR"), tried)) return *dir;
  throw std::runtime_error("no data directory with " + std::string(kDefaultConfig) + " (looked in " + tried +
                           "; install the package, or set SWUM_DATA_DIR, or give --config)");
}

fs::path default_config_path() { return data_dir() / kDefaultConfig; }

}  // namespace swum::installation
