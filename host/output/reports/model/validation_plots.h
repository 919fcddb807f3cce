// The paper-style figures of `swum validate` (model_spec §8): the free stator's tip trajectory
// by voltage and by frequency (paper Figs. 10-11), no-load speed against voltage and against
// frequency (Figs. 13-14), the frequency of maximum speed against voltage with the paper's
// values (Fig. 15) and speed against load (Fig. 16), drawn from curves computed beforehand
// (offline/validation_curves.h).
#pragma once

#include <filesystem>

#include "offline/validation_curves.h"

namespace swum::host {

/// fig13_speed_vs_voltage.png, fig14_speed_vs_frequency.png,
/// fig15_peak_frequency_vs_voltage.png, fig16_speed_vs_load.png,
/// fig10_tip_trajectory_vs_voltage.png and fig11_tip_trajectory_vs_frequency.png in `dir`
/// (which must exist), in that order. Throws as write_png_plot does.
void write_validation_plots(const ValidationCurves& curves, const std::filesystem::path& dir);

}  // namespace swum::host
