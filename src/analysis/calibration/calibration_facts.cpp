#include "analysis/calibration/calibration_facts.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>

#include "analysis/calibration/calibration_candidates.h"
#include "analysis/calibration/calibration_detail.h"
#include "analysis/fit/parameter_fit.h"
#include "analysis/steady_state/operating_curves.h"
#include "analysis/steady_state/parabola_peak.h"
#include "formats/number_format.h"

namespace swum {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kStep = 0.1;           // finite-difference step in spreads, as parameter_fit.cpp
constexpr double kPushWeight = 100.0;   // weight of a fact pushed to hold
constexpr std::size_t kMaxPushed = 3;   // failing facts pushed one by one
constexpr double kCentreWeight = 0.01;  // pull to a target inside its band (FactsProblem::cost)
// The miss of a fact the model cannot produce (no forward motion, no onset in the search range,
// a divergence), in tolerances: more than any miss of a fact whose tolerance is a sensible
// fraction of its range, so the search does not buy a missing value.
constexpr double kMissingMiss = 1000.0;

std::vector<double> speeds(const MotorModel& model, const std::vector<OperatingPoint>& points) {
  std::vector<double> out;
  for (const CurvePoint& c : run_points(model, points)) out.push_back(c.result.diverged ? kNan : c.result.speed_mm_s);
  return out;
}

// `paper_v` as the facts file quotes it; the model runs at the terminal amplitude its motor's
// options.paper_voltage_axis reads from it.
OperatingPoint point(const MotorModel& model, double paper_v, double frequency_hz, double load_n) {
  OperatingPoint p;
  p.amplitude_v = amplitude_v_of_paper_voltage(model.parameters().options.paper_voltage_axis, paper_v);
  p.frequency_hz = frequency_hz;
  p.load_n = load_n;
  return p;
}

// The peak on the walk's grid (operating_curves.h), moved to the vertex of the parabola through
// the best grid point and its neighbours (within half a fine step): the grid alone would make
// the value a staircase in the parameters.
double peak_frequency(const MotorModel& model, const Fact& f) {
  const SpeedPeak peak = frequency_of_max_speed(model, point(model, f.paper_v, 0.0, 0.0).amplitude_v, f.search_hz[0],
                                                f.search_hz[1], f.search_hz[2], f.load_n);
  if (!peak.found) return kNan;
  const double h = f.search_hz[2] / 4.0;
  const std::vector<double> s = speeds(model, {point(model, f.paper_v, peak.frequency_hz - h, f.load_n),
                                               point(model, f.paper_v, peak.frequency_hz + h, f.load_n)});
  return parabola_peak_hz(peak.frequency_hz - h, s[0], peak.frequency_hz, peak.speed_mm_s, peak.frequency_hz + h, s[1]);
}

// The lowest voltage whose speed exceeds the threshold: a 10 V grid, three bisections of the
// first crossing, then the linear interpolation of the threshold inside the last bracket.
double dead_zone_onset(const MotorModel& model, const Fact& f) {
  std::vector<OperatingPoint> grid;
  std::vector<double> voltages = evenly_spaced(f.search_paper_v[0], f.search_paper_v[1], 10.0);
  if (voltages.back() < f.search_paper_v[1]) voltages.push_back(f.search_paper_v[1]);  // the range's top, off the grid
  for (double v : voltages) grid.push_back(point(model, v, f.frequency_hz, f.load_n));
  const std::vector<double> s = speeds(model, grid);
  std::size_t i = 0;
  while (i < s.size() && !(s[i] > f.threshold_mm_s)) ++i;
  if (i == s.size()) return kNan;
  if (i == 0) return voltages[0];  // as quoted, as the fact's value
  double lo = voltages[i - 1], hi = voltages[i], s_lo = s[i - 1], s_hi = s[i];
  for (int k = 0; k < 3; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double sm = speeds(model, {point(model, mid, f.frequency_hz, f.load_n)})[0];
    if (sm > f.threshold_mm_s) {
      hi = mid;
      s_hi = sm;
    } else {
      lo = mid;
      s_lo = std::isfinite(sm) ? sm : s_lo;
    }
  }
  if (!std::isfinite(s_lo) || !(s_hi > s_lo)) return hi;
  return lo + (hi - lo) * std::clamp((f.threshold_mm_s - s_lo) / (s_hi - s_lo), 0.0, 1.0);
}

double fact_value(const MotorModel& model, const Fact& f) {
  switch (f.kind) {
    case FactKind::peak_frequency: return peak_frequency(model, f);
    case FactKind::dead_zone_onset: return dead_zone_onset(model, f);
    case FactKind::saturation_ratio: {
      std::vector<OperatingPoint> p;
      for (double v : f.ratio_paper_v) p.push_back(point(model, v, f.frequency_hz, 0.0));
      const std::vector<double> s = speeds(model, p);
      const double low = s[1] - s[0];
      return low > 0.0 ? (s[3] - s[2]) / low : kNan;
    }
    case FactKind::speed: return speeds(model, {point(model, f.paper_v, f.frequency_hz, f.load_n)})[0];
  }
  return kNan;
}

// The cost of calibration_facts.h and what it is made of, at parameter values (memoised: the
// search revisits points, and the Jacobian's base is the optimum already evaluated).
class FactsProblem {
 public:
  struct Evaluation {
    std::vector<double> facts;  // values
    Predictions predictions;    // with a measured set
    std::vector<double> residuals;
  };

  FactsProblem(const MotorParameters& prior, std::vector<FreeParameter> free, std::span<const Fact> facts,
               const MeasurementSet* measured, const ResidualModel* model, std::vector<std::size_t> train, double sigma,
               const CalibrationOptions& options, const ParallelFor& parallel, int& counter)
      : counter_(&counter),
        free_(std::move(free)),
        facts_(facts),
        measured_(measured),
        model_(model),
        train_(std::move(train)),
        sigma_(sigma),
        parallel_(parallel),
        evaluator_(prior, free_, measured != nullptr ? *measured : empty_, options.prediction, parallel, counter) {}

  [[nodiscard]] const std::vector<FreeParameter>& free() const { return free_; }
  [[nodiscard]] MotorParameters parameters_at(const std::vector<double>& values) const {
    return evaluator_.parameters_at(values);
  }

  // Evaluations at each of `value_sets` (one batch for what is not memoised).
  std::vector<const Evaluation*> evaluate(const std::vector<std::vector<double>>& value_sets) {
    std::vector<std::vector<double>> missing;
    for (const auto& v : value_sets) {
      if (memo_.find(v) == memo_.end() && std::find(missing.begin(), missing.end(), v) == missing.end()) {
        missing.push_back(v);
      }
    }
    if (!missing.empty()) {
      std::vector<MotorParameters> models;
      for (const auto& v : missing) models.push_back(evaluator_.parameters_at(v));
      const std::vector<std::vector<double>> values = evaluate_facts(models, facts_, parallel_);
      std::vector<Predictions> predictions;
      if (measured_ != nullptr) {
        predictions = evaluator_.evaluate(missing);  // counts them
      } else {
        *counter_ += static_cast<int>(missing.size());
      }
      for (std::size_t k = 0; k < missing.size(); ++k) {
        Evaluation e{values[k], {}, {}};
        if (measured_ != nullptr) {
          e.residuals = model_->residuals(predictions[k]);
          e.predictions = std::move(predictions[k]);
        }
        memo_.emplace(missing[k], std::move(e));
      }
    }
    std::vector<const Evaluation*> out;
    for (const auto& v : value_sets) out.push_back(&memo_.find(v)->second);
    return out;
  }

  [[nodiscard]] double cost(const Evaluation& e, const std::vector<double>& weights) const {
    double c = 0.0;
    for (std::size_t f = 0; f < facts_.size(); ++f) {
      const double miss = fact_miss(facts_[f], e.facts[f]);
      c += weights[f] * miss * miss;
      // A target (not a bare band) is aimed at: a faint pull to it, so that among parameter sets
      // where every fact holds (cost 0) the search prefers margin to the edges of target +- tolerance.
      if (facts_[f].target && std::isfinite(e.facts[f])) {
        const double off = (e.facts[f] - *facts_[f].target) / facts_[f].tolerance;
        c += kCentreWeight * off * off;
      }
    }
    for (std::size_t k : train_) {
      const double r = e.residuals[k] / sigma_;
      c += r * r;
    }
    return c;
  }

  // Rows of the scaled Jacobian at `values` in theta units: facts (value change / tolerance;
  // 0 where a value is missing), then training residuals / sigma.
  Eigen::MatrixXd jacobian(const std::vector<double>& values) {
    std::vector<std::vector<double>> sets{values};
    for (std::size_t k = 0; k < free_.size(); ++k) {
      std::vector<double> v = values;
      const double step = kStep * free_[k].scale;
      v[k] += v[k] + step <= std::max(free_[k].lower, free_[k].upper) ? step : -step;
      sets.push_back(v);
    }
    const std::vector<const Evaluation*> e = evaluate(sets);
    const auto rows = static_cast<Eigen::Index>(facts_.size() + train_.size());
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(rows, static_cast<Eigen::Index>(free_.size()));
    for (std::size_t k = 0; k < free_.size(); ++k) {
      const double dtheta = (sets[k + 1][k] - values[k]) / free_[k].scale;
      const auto col = static_cast<Eigen::Index>(k);
      for (std::size_t f = 0; f < facts_.size(); ++f) {
        // A target is a measurement with sigma = tolerance: the slope of its value. A bare band
        // says nothing about where inside it the value lies: it informs only while it is active,
        // missed at either end of the step (then the slope of its value, whichever way the step
        // went); a fact that holds with room to spare determines no parameter.
        const Fact& fact = facts_[f];
        const double v0 = e[0]->facts[f], v1 = e[k + 1]->facts[f];
        const bool informs = fact.target || fact_miss(fact, v0) > 0.0 || fact_miss(fact, v1) > 0.0;
        const double d = (v1 - v0) / (dtheta * fact.tolerance);
        j(static_cast<Eigen::Index>(f), col) = informs && std::isfinite(d) ? d : 0.0;
      }
      for (std::size_t i = 0; i < train_.size(); ++i) {
        const std::size_t s = train_[i];
        j(static_cast<Eigen::Index>(facts_.size() + i), col) = (e[k + 1]->residuals[s] - e[0]->residuals[s]) /
                                                               (dtheta * sigma_);
      }
    }
    return j;
  }

 private:
  int* counter_;
  std::vector<FreeParameter> free_;
  std::span<const Fact> facts_;
  const MeasurementSet* measured_;
  const ResidualModel* model_;
  std::vector<std::size_t> train_;
  double sigma_;
  ParallelFor parallel_;
  MeasurementSet empty_;
  ParameterEvaluator evaluator_;
  std::map<std::vector<double>, Evaluation> memo_;
};

struct SearchResult {
  std::vector<double> values;
  double cost = kInfinity;
  int evaluations = 0;
};

// Derivative-free bounded minimisation of the weighted cost from `start` (NLopt Subplex in
// theta units, initial step a quarter spread). The best point seen is kept whatever NLopt's
// return code (a round-off stop or the budget).
SearchResult search(FactsProblem& problem, const std::vector<double>& start, const std::vector<double>& weights,
                    int budget) {
  const std::vector<FreeParameter>& free = problem.free();
  const std::size_t m = free.size();
  std::vector<double> lo(m), hi(m), theta(m);
  for (std::size_t k = 0; k < m; ++k) {
    lo[k] = (free[k].lower - free[k].origin) / free[k].scale;
    hi[k] = (free[k].upper - free[k].origin) / free[k].scale;
    if (lo[k] > hi[k]) std::swap(lo[k], hi[k]);
    theta[k] = std::clamp((start[k] - free[k].origin) / free[k].scale, lo[k], hi[k]);
  }
  nlopt::opt opt(nlopt::LN_SBPLX, static_cast<unsigned>(m));
  struct Context {
    FactsProblem* problem;
    const std::vector<double>* weights;
    nlopt::opt* opt;
    SearchResult best;
    std::exception_ptr error;  // what the cost threw: rethrown, never taken for a result
  } context{&problem, &weights, &opt, {}, nullptr};
  auto values_of = [&free](const std::vector<double>& t) {
    std::vector<double> v(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) v[k] = free[k].origin + t[k] * free[k].scale;
    return v;
  };
  auto objective = [](const std::vector<double>& t, std::vector<double>&, void* data) {
    auto* c = static_cast<Context*>(data);
    const std::vector<FreeParameter>& fp = c->problem->free();
    std::vector<double> v(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) v[k] = fp[k].origin + t[k] * fp[k].scale;
    double cost = 0.0;
    try {
      cost = c->problem->cost(*c->problem->evaluate({v})[0], *c->weights);
    } catch (...) {
      c->error = std::current_exception();
      c->opt->force_stop();
      return 1e300;
    }
    ++c->best.evaluations;
    if (cost < c->best.cost) {
      c->best.cost = cost;
      c->best.values = v;
    }
    return std::isfinite(cost) ? cost : 1e300;
  };
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(+objective, &context);
  opt.set_maxeval(std::max(budget, 2));
  opt.set_xtol_abs(1e-3);  // a thousandth of a spread
  opt.set_ftol_abs(1e-4);
  std::vector<double> step(m);
  for (std::size_t k = 0; k < m; ++k) step[k] = std::min(0.25, 0.5 * (hi[k] - lo[k]));
  opt.set_initial_step(step);
  double minimum = 0.0;
  try {
    opt.optimize(theta, minimum);
  } catch (const nlopt::roundoff_limited&) {
    // Round-off ended the search: the best point seen stands.
  } catch (const nlopt::forced_stop&) {
    // Only the cost forces a stop, after storing what it threw.
  }
  if (context.error) std::rethrow_exception(context.error);
  if (context.best.values.empty()) context.best.values = values_of(theta);
  return context.best;
}

}  // namespace

double fact_miss(const Fact& fact, double value) {
  if (!std::isfinite(value)) return kMissingMiss;
  if (value < fact.min) return (fact.min - value) / fact.tolerance;
  if (value > fact.max) return (value - fact.max) / fact.tolerance;
  return 0.0;
}

std::vector<std::vector<double>> evaluate_facts(std::span<const MotorParameters> models, std::span<const Fact> facts,
                                                const ParallelFor& parallel) {
  std::vector<std::unique_ptr<MotorModel>> built(models.size());
  parallel(models.size(), [&](std::size_t k) { built[k] = std::make_unique<MotorModel>(models[k]); });
  std::vector<std::vector<double>> out(models.size(), std::vector<double>(facts.size(), kNan));
  parallel(models.size() * facts.size(), [&](std::size_t task) {
    const std::size_t m = task / facts.size(), f = task % facts.size();
    out[m][f] = fact_value(*built[m], facts[f]);
  });
  return out;
}

CalibrationResult calibrate_to_facts(const MotorParameters& prior, std::span<const Fact> facts,
                                     const MeasurementSet* measured, const CalibrationOptions& options,
                                     const ParallelFor& parallel) {
  if (facts.empty()) throw std::invalid_argument("no facts");
  if (options.max_free < 1) throw std::invalid_argument("max_free must be >= 1");
  if (options.starts < 1) throw std::invalid_argument("starts must be >= 1");
  CalibrationResult result;
  std::optional<ResidualModel> model;
  std::vector<std::size_t> train, test;
  double sigma = 1.0;
  if (measured != nullptr) {
    model.emplace(*measured, options.floor_fraction);
    result.held_out = held_out_rows(*measured, options.split, result.held_out_points, result.operating_points);
    for (std::size_t k = 0; k < model->slots().size(); ++k) {
      (result.held_out[model->slots()[k].row] ? test : train).push_back(k);
    }
  }
  const bool choose = options.free.empty();
  const std::vector<FreeParameter> pool = calibration_pool(options, prior);

  // The prior (and the noise of the measured set, which scales its residuals).
  if (measured != nullptr) {
    int ignored = 0;
    const ParameterEvaluator prior_eval(prior, {}, *measured, options.prediction, parallel, ignored);
    result.prior_predictions = prior_eval.evaluate({{}})[0];
    ++result.model_evaluations;
    const DisagreementMap map = map_disagreement(*measured, result.prior_predictions, *model);
    result.noise = map.noise;
    result.noise_source = map.noise_source;
    sigma = std::max(result.noise, options.min_noise);
  }
  const std::vector<double> ones(facts.size(), 1.0);
  auto origins = [](const std::vector<FreeParameter>& f) {
    std::vector<double> v;
    for (const FreeParameter& p : f) v.push_back(p.origin);
    return v;
  };

  std::vector<FreeParameter> free;
  std::vector<double> prior_facts;
  {
    FactsProblem pool_problem(prior, pool, facts, measured, model ? &*model : nullptr, train, sigma, options, parallel,
                              result.model_evaluations);
    prior_facts = pool_problem.evaluate({origins(pool)})[0]->facts;
    if (choose) {
      const Eigen::MatrixXd j = pool_problem.jacobian(origins(pool));
      for (std::size_t k : select_free_set(j, pool, options, result.selection)) free.push_back(pool[k]);
    } else {
      free = pool;
    }
  }

  std::vector<CalibratedParameter> dropped;
  std::vector<double> start = origins(free);
  std::optional<SearchResult> fit;
  std::shared_ptr<FactsProblem> problem;
  std::vector<double> standard_errors;
  Eigen::MatrixXd covariance;
  std::mt19937_64 rng(options.seed);
  std::vector<double> explored_facts = prior_facts;
  std::shared_ptr<FactsProblem> explore_problem;  // round 1: every free parameter moving
  std::vector<double> explored_values;
  while (!free.empty()) {
    ++result.rounds;
    problem = std::make_shared<FactsProblem>(prior, free, facts, measured, model ? &*model : nullptr, train, sigma,
                                             options, parallel, result.model_evaluations);
    const std::vector<std::vector<double>> starts = fit_starts(start, free, result.rounds == 1 ? options.starts : 1,
                                                               rng);
    const int budget = std::max(options.max_evaluations / static_cast<int>(starts.size()),
                                4 * static_cast<int>(free.size()));
    std::optional<SearchResult> best;
    for (const std::vector<double>& s : starts) {
      SearchResult r = search(*problem, s, ones, budget);
      ++result.starts_run;
      if (!best || r.cost < best->cost) best = std::move(r);
    }
    // Standard errors from the scaled Jacobian at the optimum; a tiny ridge makes a flat
    // direction show as huge errors of the parameters along it instead of a failed inverse.
    const Eigen::MatrixXd j = problem->jacobian(best->values);
    const Eigen::MatrixXd information = j.transpose() * j;
    const double ridge = 1e-10 * std::max(information.trace(), 1e-300);
    covariance = (information + ridge * Eigen::MatrixXd::Identity(information.rows(), information.cols()))
                     .ldlt()
                     .solve(Eigen::MatrixXd::Identity(information.rows(), information.cols()));
    standard_errors.assign(free.size(), kInfinity);
    for (std::size_t k = 0; k < free.size(); ++k) {
      const double var = covariance(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
      if (var > 0.0 && std::isfinite(var)) standard_errors[k] = std::sqrt(var) * std::abs(free[k].scale);
    }
    if (result.rounds == 1) {
      for (std::size_t k = 0; k < free.size(); ++k) result.explored.emplace_back(free[k].name, best->values[k]);
      explored_facts = problem->evaluate({best->values})[0]->facts;
      explore_problem = problem;
      explored_values = best->values;
    }
    const Undetermined worst = least_determined(best->values, standard_errors, free, options);
    if (!worst.index) {
      fit = std::move(best);
      break;
    }
    start = best->values;
    dropped.push_back(hold_at_prior(worst, free, start));
  }

  result.fitted = prior;
  std::vector<double> fitted_facts = prior_facts;
  if (fit) {
    for (std::size_t k = 0; k < free.size(); ++k) {
      const FreeParameter& f = free[k];
      f.apply(result.fitted, fit->values[k]);
      const double v = fit->values[k];
      result.parameters.push_back({f.name, f.unit, f.origin, std::abs(f.scale), v, standard_errors[k], f.lower, f.upper,
                                   true, at_bound(f, v), ""});
    }
    result.correlations.assign(free.size(), std::vector<double>(free.size()));
    for (std::size_t a = 0; a < free.size(); ++a) {
      for (std::size_t b = 0; b < free.size(); ++b) {
        const auto ia = static_cast<Eigen::Index>(a), ib = static_cast<Eigen::Index>(b);
        result.correlations[a][b] = covariance(ia, ib) / std::sqrt(covariance(ia, ia) * covariance(ib, ib));
      }
    }
    const FactsProblem::Evaluation& at_fit = *problem->evaluate({fit->values})[0];
    fitted_facts = at_fit.facts;
    if (measured != nullptr) result.fitted_predictions = at_fit.predictions;
  } else if (measured != nullptr) {
    result.fitted_predictions = result.prior_predictions;
  }
  for (const CalibratedParameter& p : dropped) result.parameters.push_back(p);

  for (std::size_t f = 0; f < facts.size(); ++f) {
    const Fact& fact = facts[f];
    result.facts.push_back({fact.id, std::string(fact.unit()), fact.min, fact.max, prior_facts[f], fitted_facts[f],
                            explored_facts[f], fact_miss(fact, prior_facts[f]) == 0.0,
                            fact_miss(fact, fitted_facts[f]) == 0.0, fact_miss(fact, explored_facts[f]) == 0.0});
  }

  // Which facts failing with every free parameter moving can be pushed to hold, what breaks
  // then, and the front of the first conflict (on the first round's free set).
  if (explore_problem && options.trade_offs) {
    FactsProblem& explore = *explore_problem;
    const int budget = std::max(options.max_evaluations / 2, 4 * static_cast<int>(explored_values.size()));
    for (std::size_t f = 0; f < facts.size() && result.reach.size() < kMaxPushed; ++f) {
      if (result.facts[f].holds_explored) continue;
      std::vector<double> weights = ones;
      weights[f] = kPushWeight;
      const SearchResult pushed = search(explore, explored_values, weights, budget);
      const std::vector<double> values = explore.evaluate({pushed.values})[0]->facts;
      FactReach reach{facts[f].id, fact_miss(facts[f], values[f]) == 0.0, values[f], {}};
      // The facts it trades against: their miss grows (those that held and then fail, or fail
      // by more); the front is traced against the one that loses most.
      std::optional<std::size_t> conflict;
      double largest_growth = 0.0;
      for (std::size_t g = 0; g < facts.size(); ++g) {
        const double growth = fact_miss(facts[g], values[g]) - fact_miss(facts[g], explored_facts[g]);
        if (g == f || !(growth > 1e-3)) continue;
        reach.breaks.push_back(facts[g].id);
        if (growth > largest_growth) {
          largest_growth = growth;
          conflict = g;
        }
      }
      result.reach.push_back(reach);
      if (conflict && result.fronts.empty()) {
        FactFront front{facts[f].id, facts[*conflict].id, {}, {}, {}, {}, {}};
        std::vector<double> at = explored_values;
        for (double w : {1.0, 3.0, 10.0, 30.0, kPushWeight}) {
          std::vector<double> v;
          if (w == 1.0) {
            v = explored_facts;
          } else if (w == kPushWeight) {
            v = values;
          } else {
            weights[f] = w;
            at = search(explore, at, weights, budget / 2).values;
            v = explore.evaluate({at})[0]->facts;
          }
          front.weights.push_back(w);
          front.first_values.push_back(v[f]);
          front.second_values.push_back(v[*conflict]);
          front.first_misses.push_back(fact_miss(facts[f], v[f]));
          front.second_misses.push_back(fact_miss(facts[*conflict], v[*conflict]));
        }
        result.fronts.push_back(front);
      }
    }
  }

  if (measured != nullptr) score_on_measurements(*measured, *model, train, test, options, result);
  int identified = 0, holding = 0;
  for (const CalibratedParameter& p : result.parameters) identified += p.identifiable ? 1 : 0;
  for (const FactOutcome& f : result.facts) holding += f.holds ? 1 : 0;
  result.conclusion = std::to_string(identified) + " of " + std::to_string(result.parameters.size()) +
                      " free parameters identified" +
                      (choose ? " (chosen from " + std::to_string(pool.size()) + " candidates)" : "") + "; " +
                      std::to_string(holding) + " of " + std::to_string(facts.size()) + " facts hold";
  if (measured != nullptr) {
    result.conclusion += format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * result.held_out_rms_prior,
                                        100.0 * result.held_out_rms);
  }
  return result;
}

}  // namespace swum
