// swum calibrate's fits (src/analysis/calibration/calibration.h, calibration_facts.h) on data made by the
// model itself: a motor with perturbed base parameters is measured (synthesised sweeps with 2 %
// noise, or its facts), the calibration starts from the unperturbed motor and must recover the
// perturbation within its reported uncertainty, report what the data cannot determine, and say
// which facts trade against each other.
#include "analysis/calibration/calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "../discrepancy_test_support.h"
#include "../thread_pool_for.h"
#include "analysis/calibration/calibration_candidates.h"
#include "analysis/calibration/calibration_facts.h"
#include "analysis/measurements/synthetic_measurements.h"

namespace swum {
namespace {

constexpr double kNoise = 0.02;

void set(MotorParameters& p, std::string_view name, double value) {
  const std::size_t dot = name.find('.');
  find_parameter_spec(name.substr(0, dot), name.substr(dot + 1))->set(p, value);
}

// The perturbed motor: four parameters of the default free set moved by 0.3-1 prior spreads.
const std::map<std::string, double>& truth() {
  static const std::map<std::string, double> t{{"contact.preload_n", 22.5},
                                               {"stator.damping_l1_n_s_m", 44.0},
                                               {"contact.friction_coefficient", 0.33},
                                               {"stator.c1111_pa", -1.0e17}};
  return t;
}

MotorParameters perturbed_motor() {
  MotorParameters p = test::calibrated_motor();
  for (const auto& [name, value] : truth()) set(p, name, value);
  return p;
}

// Sweeps down through the resonance at three voltages and two loads, as `swum sweep` takes them.
std::vector<Measurement> sweep_points() {
  std::vector<Measurement> points;
  int sweep = 0;
  for (double load : {0.0, 2.0}) {
    for (double amplitude_v : {150.0, 250.0, 350.0}) {
      for (double f = 41000.0; f >= 39100.0; f -= 100.0) {
        Measurement m;
        m.amplitude_v = amplitude_v;
        m.frequency_hz = f;
        m.load_n = load;
        m.sweep = sweep;
        points.push_back(m);
      }
      ++sweep;
    }
  }
  return points;
}

struct SweepData {
  MeasurementSet noisy, exact;
};

const SweepData& sweep_data() {
  static const SweepData data = [] {
    SynthOptions o;
    o.quantities = {true, false, false};
    o.relative_noise = kNoise;
    o.seed = 17;
    SynthOptions exact = o;
    exact.relative_noise = 0.0;
    const std::vector<Measurement> points = sweep_points();
    return SweepData{synthesize_measurements(perturbed_motor(), points, o, test::two_thread_for),
                     synthesize_measurements(perturbed_motor(), points, exact, test::two_thread_for)};
  }();
  return data;
}

const CalibratedParameter& parameter(const CalibrationResult& r, std::string_view name) {
  for (const CalibratedParameter& p : r.parameters) {
    if (p.name == name) return p;
  }
  throw std::runtime_error("no parameter " + std::string(name));
}

void expect_recovered(const CalibrationResult& r) {
  for (const auto& [name, value] : truth()) {
    const CalibratedParameter& p = parameter(r, name);
    ASSERT_TRUE(p.identifiable) << name << ": " << p.reason;
    EXPECT_LE(std::abs(p.value - value), 3.0 * p.standard_error)
        << name << " = " << p.value << " +- " << p.standard_error << ", truth " << value;
    EXPECT_LT(p.standard_error, 0.5 * p.spread) << name;
  }
}

TEST(Calibration, RoundTripRecoversThePerturbationAndHoldsWhatTheDataCannotDetermine) {
  const SweepData& data = sweep_data();
  CalibrationOptions o;
  o.free = {"contact.preload_n", "stator.damping_l1_n_s_m", "contact.friction_coefficient", "stator.c1111_pa",
            "stator.e311_c_per_v_m"};
  const CalibrationResult r = calibrate_to_measurements(test::calibrated_motor(), data.noisy, o, test::two_thread_for);
  expect_recovered(r);
  // e311, the quadratic voltage-dependent stiffness, is flat in speed sweeps (as in free-stator
  // amplitudes, docs/identification.md): reported, held at its prior, the others refitted.
  const CalibratedParameter& e311 = parameter(r, "stator.e311_c_per_v_m");
  EXPECT_FALSE(e311.identifiable);
  EXPECT_FALSE(std::isfinite(e311.standard_error));
  EXPECT_EQ(e311.value, e311.prior);
  EXPECT_NE(e311.reason.find("held at its prior"), std::string::npos) << e311.reason;
  EXPECT_EQ(r.fitted.stator.e311_c_per_v_m, test::calibrated_motor().stator.e311_c_per_v_m);
  EXPECT_GE(r.rounds, 2);
  // Within the noise on held-out points: as close to the noise-free truth as the noise allows.
  EXPECT_LT(test::held_out_gap(data.exact, r.fitted_predictions, r.held_out), 0.5 * kNoise);
  EXPECT_GT(test::held_out_gap(data.exact, r.prior_predictions, r.held_out), 5.0 * kNoise);
  EXPECT_LT(r.held_out_evidence.p_value, 1e-3);
  // The correlations are those of the identified parameters: unit diagonal, |rho| <= 1.
  ASSERT_EQ(r.correlations.size(), truth().size());
  for (std::size_t a = 0; a < r.correlations.size(); ++a) {
    EXPECT_NEAR(r.correlations[a][a], 1.0, 1e-9);
    for (double rho : r.correlations[a]) EXPECT_LE(std::abs(rho), 1.0 + 1e-9);
  }
}

TEST(Calibration, DefaultFreeSetComesFromTheFisherInformationOfTheDesign) {
  const SweepData& data = sweep_data();
  CalibrationOptions o;  // no free set: chosen among every applicable candidate
  const CalibrationResult r = calibrate_to_measurements(test::calibrated_motor(), data.noisy, o, test::two_thread_for);
  ASSERT_EQ(r.selection.size(), applicable_candidates(test::calibrated_motor()).size());
  int selected = 0;
  for (const CandidateInformation& c : r.selection) {
    selected += c.selected ? 1 : 0;
    if (!c.selected) {
      EXPECT_FALSE(c.reason.empty()) << c.name;
    }
  }
  EXPECT_EQ(selected, o.max_free);
  // The selected ones come first in the order of preference, and the set is full: the rest
  // say so.
  for (std::size_t k = 0; k < r.selection.size(); ++k) {
    EXPECT_EQ(r.selection[k].selected, k < static_cast<std::size_t>(o.max_free)) << r.selection[k].name;
    if (k >= static_cast<std::size_t>(o.max_free)) {
      EXPECT_NE(r.selection[k].reason.find("full"), std::string::npos) << r.selection[k].reason;
    }
  }
  expect_recovered(r);
  // The unperturbed members of the set stay at their truth (= prior) within their uncertainty.
  for (const CalibratedParameter& p : r.parameters) {
    if (truth().count(p.name) != 0 || !p.identifiable) continue;
    EXPECT_LE(std::abs(p.value - p.prior), 3.0 * p.standard_error) << p.name;
  }
  EXPECT_LT(test::held_out_gap(data.exact, r.fitted_predictions, r.held_out), 0.5 * kNoise);
}

TEST(Calibration, BadFreeSetsAreRefusedBeforeAnyFit) {
  const MotorParameters prior = test::calibrated_motor();
  const MeasurementSet& data = sweep_data().noisy;
  CalibrationOptions o;
  o.free = {"contact.no_such_key"};
  EXPECT_THROW((void)calibrate_to_measurements(prior, data, o, serial_for), std::invalid_argument);
  o.free = {"contact.preload_n", "contact.preload_n"};
  EXPECT_THROW((void)calibrate_to_measurements(prior, data, o, serial_for), std::invalid_argument);
  MotorParameters rigid = prior;
  rigid.contact.tangential_stiffness_n_m = 0.0;
  o.free = {"contact.tangential_stiffness_n_m"};
  EXPECT_THROW((void)calibrate_to_measurements(rigid, data, o, serial_for), std::invalid_argument);
  o.free = {};
  o.max_free = 0;
  EXPECT_THROW((void)calibrate_to_measurements(prior, data, o, serial_for), std::invalid_argument);
}

Fact speed_fact(double paper_v, double value, double relative_tolerance) {
  Fact f;
  f.kind = FactKind::speed;
  f.id = "speed at " + std::to_string(static_cast<int>(paper_v)) + " V";
  f.paper_v = paper_v;  // the calibrated motor reads it as the amplitude
  f.frequency_hz = 40000.0;
  f.target = value;
  f.tolerance = relative_tolerance * std::abs(value);
  f.min = value - f.tolerance;
  f.max = value + f.tolerance;
  return f;
}

TEST(CalibrationFacts, FactsOfAPerturbedMotorBringItsParameterBack) {
  MotorParameters truth_motor = test::calibrated_motor();
  truth_motor.stator.damping_l1_n_s_m = 44.0;
  Fact peak;
  peak.kind = FactKind::peak_frequency;
  peak.id = "peak at 250 V";
  peak.paper_v = 250.0;
  std::vector<Fact> facts{peak, speed_fact(300.0, 1.0, 0.02)};
  const std::vector<double> values = evaluate_facts({&truth_motor, 1}, facts, test::two_thread_for)[0];
  ASSERT_TRUE(std::isfinite(values[0]) && std::isfinite(values[1]));
  facts[0].target = values[0];
  facts[0].tolerance = 25.0;
  facts[0].min = values[0] - 25.0;
  facts[0].max = values[0] + 25.0;
  facts[1] = speed_fact(300.0, values[1], 0.01);

  CalibrationOptions o;
  o.free = {"stator.damping_l1_n_s_m", "mover.mass_kg"};
  o.max_evaluations = 80;
  const CalibrationResult r = calibrate_to_facts(test::calibrated_motor(), facts, nullptr, o, test::two_thread_for);
  ASSERT_EQ(r.facts.size(), 2u);
  EXPECT_FALSE(r.facts[1].holds_prior) << r.facts[1].prior_value << " vs " << values[1];
  for (const FactOutcome& f : r.facts) EXPECT_TRUE(f.holds) << f.id << ": " << f.value;
  const CalibratedParameter& damping = parameter(r, "stator.damping_l1_n_s_m");
  ASSERT_TRUE(damping.identifiable) << damping.reason;
  EXPECT_NEAR(damping.value, 44.0, std::max(3.0 * damping.standard_error, 0.5));
  EXPECT_FALSE(parameter(r, "mover.mass_kg").identifiable);
  EXPECT_TRUE(r.reach.empty());
}

TEST(CalibrationFacts, ConflictingFactsAreNamedWithTheFrontBetweenThem) {
  // With the L1 damping alone free, a faster motor at 300 V and a slower one at 150 V
  // cannot both be had: less damping speeds both up.
  const MotorParameters prior = test::calibrated_motor();
  const std::vector<Fact> probe{speed_fact(300.0, 1.0, 0.1), speed_fact(150.0, 1.0, 0.1)};
  const std::vector<double> v = evaluate_facts({&prior, 1}, probe, test::two_thread_for)[0];
  std::vector<Fact> facts{speed_fact(300.0, 1.15 * v[0], 0.02), speed_fact(150.0, 0.85 * v[1], 0.02)};
  CalibrationOptions o;
  o.free = {"stator.damping_l1_n_s_m"};
  o.max_evaluations = 60;
  const CalibrationResult r = calibrate_to_facts(prior, facts, nullptr, o, test::two_thread_for);
  ASSERT_EQ(r.facts.size(), 2u);
  EXPECT_FALSE(r.facts[0].holds_explored && r.facts[1].holds_explored);
  // Both fail at the compromise; pushed alone, each makes the other fail by more.
  ASSERT_EQ(r.reach.size(), 2u);
  for (const FactReach& reach : r.reach) {
    ASSERT_EQ(reach.breaks.size(), 1u) << reach.id;
    EXPECT_NE(reach.breaks[0], reach.id);
  }
  ASSERT_EQ(r.fronts.size(), 1u);
  const FactFront& front = r.fronts[0];
  EXPECT_NE(front.first, front.second);
  ASSERT_EQ(front.weights.size(), 5u);
  // Along the front the pushed fact's miss falls and the other's grows.
  EXPECT_LT(front.first_misses.back(), front.first_misses.front());
  EXPECT_GT(front.second_misses.back(), front.second_misses.front());
  for (std::size_t k = 1; k < front.weights.size(); ++k) {
    EXPECT_LE(front.first_misses[k], front.first_misses[k - 1] + 0.05) << k;
  }
}

TEST(CalibrationFacts, MissIsTheDistanceOutsideTheBandInTolerances) {
  Fact f = speed_fact(100.0, 50.0, 0.1);  // band 45..55, tolerance 5
  EXPECT_EQ(fact_miss(f, 50.0), 0.0);
  EXPECT_EQ(fact_miss(f, 55.0), 0.0);
  EXPECT_DOUBLE_EQ(fact_miss(f, 60.0), 1.0);
  EXPECT_DOUBLE_EQ(fact_miss(f, 35.0), 2.0);
  EXPECT_EQ(fact_miss(f, std::nan("")), 1000.0);  // more than any finite miss
}

}  // namespace
}  // namespace swum
