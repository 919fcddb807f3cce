// A TOML integer or float as a double (the parameter, spreads and facts files all accept
// `24` for `24.0`); nullopt for any other type. Included by the config parsers only (toml++ is
// their private dependency).
#pragma once

#include <optional>

#include <toml++/toml.h>

namespace swum {

[[nodiscard]] inline std::optional<double> toml_number(const toml::node& node) {
  if (const auto* f = node.as_floating_point()) return f->get();
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  return std::nullopt;
}

}  // namespace swum
