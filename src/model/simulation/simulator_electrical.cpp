// MotorSimulator::advance with the electrical port (model/machine/electrical.h), in its own translation
// unit: see simulator_loop.h.
#include "model/simulation/simulator_loop.h"

namespace swum {

void MotorSimulator::advance(std::uint64_t steps, ElectricalSums& sums) {
  system_.dispatch([&]<TangentialContact C, GuideFrictionModel G>() {
    faults_.jammed ? advance_specialised<C, G, false, true, true>(steps, nullptr, &sums)
                   : advance_specialised<C, G, false, false, true>(steps, nullptr, &sums);
  });
}

void MotorSimulator::advance(std::uint64_t steps, WindowStatistics& window, ElectricalSums& sums) {
  system_.dispatch([&]<TangentialContact C, GuideFrictionModel G>() {
    faults_.jammed ? advance_specialised<C, G, true, true, true>(steps, &window, &sums)
                   : advance_specialised<C, G, true, false, true>(steps, &window, &sums);
  });
}

}  // namespace swum
