// Steady states of many operating points at once (issue 16): run_to_steady_state's procedure
// (settle, then windows until two agree, the same rules: steady_state.h) with the points in the
// SIMD lanes of a BatchSimulator. Points come in chains: the points of a chain run one after the
// other, each from the state the previous one left (a sweep: the motor's hysteresis), so a chain
// stays in one lane; independent chains fill the lanes, and a lane whose chain is done takes the
// next pending chain (a work queue: lanes do not idle while work is left).
//
// The results are those of run_to_steady_state point by point, to rounding (the lanes contract
// multiply-adds differently from the scalar step), and do not depend on the lane count or on the
// order in which lanes pick chains. Where the lanes do not implement the model or the options
// (batch_steady_state_supported), the same functions run the scalar path: the same results,
// exactly those of run_to_steady_state.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "analysis/steady_state/steady_state.h"
#include "model/motor_model.h"

namespace swum {

// Points run one after the other; each after the first starts from the state the previous one
// left (SteadyStateResult::final_state; its own initial_state is ignored), the first from its
// initial_state or at rest.
using OperatingChain = std::vector<OperatingPoint>;

// Called on the calling thread as soon as a point's result is final (chains complete out of
// order; within a chain, in order). What it throws stops the run as ParallelFor stops a batch:
// no new point starts, the points under way in other lanes finish and are reported (what the
// callback throws then is dropped), and the first exception is rethrown.
using ChainPointDone = std::function<void(std::size_t chain, std::size_t index, const SteadyStateResult& result)>;

// Lanes of one batch: 16 doubles are two AVX-512 vectors (or four AVX2 ones), enough
// independent work per step to hide the step's latency (docs/performance.md, issue 16).
inline constexpr std::size_t kDefaultBatchLanes = 16;

// Whether the lanes run points with these options: BatchSimulator::supports(model), no trace,
// and settle and window lengths of whole 64-step housekeeping blocks (so that every point starts
// its blocks where a fresh MotorSimulator does). With thermal or wear the lanes also need every
// point's slow states frozen (OperatingPoint::freeze_slow_states, as predictions of measured
// points have them); run_chains_to_steady_state checks that and otherwise runs the scalar path.
[[nodiscard]] bool batch_steady_state_supported(const MotorModel& model, const SteadyStateOptions& options);

// results[c][k] for chains[c][k]. One thread; `lanes` lanes at most (fewer for fewer chains).
[[nodiscard]] std::vector<std::vector<SteadyStateResult>> run_chains_to_steady_state(
    const MotorModel& model, std::span<const OperatingChain> chains, const SteadyStateOptions& options = {},
    std::size_t lanes = kDefaultBatchLanes, const ChainPointDone& point_done = {});

// Independent points (chains of one point each, each from its own initial_state or rest).
[[nodiscard]] std::vector<SteadyStateResult> run_points_to_steady_state(const MotorModel& model,
                                                                        std::span<const OperatingPoint> points,
                                                                        const SteadyStateOptions& options = {},
                                                                        std::size_t lanes = kDefaultBatchLanes);

}  // namespace swum
