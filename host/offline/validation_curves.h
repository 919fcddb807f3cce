// The curves behind `swum validate`'s paper-style figures (paper Figs. 10-11, 13-16), computed
// on the model and its linear variant on this machine's cores; output/reports/model/validation_plots.h
// draws them. Each curve holds the points the model reached: a run that diverged is left out.
#pragma once

#include <vector>

#include "analysis/studies/paper_facts.h"
#include "model/motor_model.h"
#include "model/parameters.h"

namespace swum::host {

/// The points of one curve, in the order they were run.
struct XyCurve {
  std::vector<double> x;
  std::vector<double> y;
};

/// No-load speed (mm/s) against drive frequency (kHz) at one voltage (Fig. 14).
struct FrequencyCurves {
  double paper_v = 0.0;  // on the paper's axis (its label "Vpp")
  XyCurve nonlinear;
  XyCurve linear;
};

/// Speed (mm/s) against load (N) of the non-linear model at one drive (Fig. 16).
struct LoadCurve {
  double paper_v = 0.0;  // on the paper's axis (its label "Vpp")
  double frequency_hz = 0.0;
  XyCurve speed;
};

/// The free stator's tip over the last drive period of a 30 ms run (Figs. 10-11): x the
/// tangential, y the normal displacement (um).
struct TipOrbit {
  double paper_v = 0.0;  // on the paper's axis (its label "Vpp")
  double frequency_hz = 0.0;
  XyCurve tip_um;
};

struct ValidationCurves {
  XyCurve speed_vs_voltage_nonlinear;  // Fig. 13: mm/s against the paper's V ("Vpp"), 40 kHz, no load
  XyCurve speed_vs_voltage_linear;
  std::vector<FrequencyCurves> speed_vs_frequency;  // Fig. 14: 100, 250, 400 Vpp, 39-41 kHz
  XyCurve peak_vs_voltage_nonlinear;                // Fig. 15: kHz of the speed peak against the paper's V
  XyCurve peak_vs_voltage_linear;
  std::vector<LoadCurve> speed_vs_load;      // Fig. 16: drift-aware and naive frequency at 300 and 400 Vpp
  std::vector<TipOrbit> orbit_vs_voltage;    // Fig. 10: 100-400 Vpp at 39.5 kHz
  std::vector<TipOrbit> orbit_vs_frequency;  // Fig. 11: 39.0, 39.2, 39.5 kHz at 400 Vpp
};

/// Every curve of the figures. `nonlinear` and `linear` are the models of `parameters` and of
/// its linearised variant; `facts` (on the same two models) finds and memoises the speed peaks.
ValidationCurves validation_curves(const MotorParameters& parameters, const MotorModel& nonlinear,
                                   const MotorModel& linear, PaperFacts& facts);

}  // namespace swum::host
