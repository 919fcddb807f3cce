// The dashboard's files (firmware_sim/dashboard/: the page, its script and style, and uPlot from
// npm at the version package-lock.json pins), embedded in swum-emu at build time
// (dashboard/embed.cmake): the page loads nothing from anywhere but the emulator.
#pragma once

#include <span>
#include <string_view>

namespace swum::emu {

struct DashboardAsset {
  std::string_view path;  // "index.html", "dashboard.js", "uPlot.iife.min.js", ...
  std::string_view content_type;
  std::string_view body;
};

std::span<const DashboardAsset> dashboard_assets();

}  // namespace swum::emu
