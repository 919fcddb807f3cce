// The HTTP API's JSON (docs/http-api.md, docs/openapi.yaml): the telemetry snapshot, the loop
// statistics, the fault types and the faults in force out; a fault request in. Pure: values in,
// JSON out (nlohmann), no sockets, no clock, so tests check it directly.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/shared_state.h"

namespace swum::emu {

// A request the API refuses: the HTTP status (4xx) and one line saying why.
class HttpError : public std::runtime_error {
 public:
  HttpError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  [[nodiscard]] int status() const { return status_; }

 private:
  int status_;
};

// Where the motor's resonances are now (ResonancePeak): the free stator's softening peaks of
// both modes at the drive amplitude (harmonic balance), shifted by the stator temperature.
struct ResonanceEstimate {
  double amplitude_v = 0.0;
  double normal_peak_hz = 0.0;      // L1
  double tangential_peak_hz = 0.0;  // B2
};

// The loop's timing figures (state.loop and stats.loop).
nlohmann::json loop_json(const protocol::LoopTiming& loop);

// GET /api/v1/state: every telemetry field (SI units, names as in protocol/telemetry.h), the
// reject log and the resonance estimate.
// `canopen_nmt_state`: SharedState::canopen_nmt_state (kNoCanopen: "canopen" is null).
nlohmann::json state_json(const Telemetry& t, const RejectSnapshot& rejects, const ResonanceEstimate& resonance,
                          std::uint8_t canopen_nmt_state = SharedState::kNoCanopen);

// GET /api/v1/faults: the types the API accepts (the scenario faults, with their keys and
// ranges) and the faults in force.
nlohmann::json fault_types_json();
nlohmann::json active_faults_json(const ActiveFaults& faults, double tick_hz);

// POST /api/v1/faults body: {"type": "phase_open", "phase": "B", "duration_s": 0.1}. The keys,
// ranges and messages are a scenario file's (docs/scenarios.md); only faults (and a clear
// naming one) are accepted. Throws HttpError 400: malformed JSON, a key given twice, a body
// that is not an object, an unknown or non-fault type, a bad key or value.
RuntimeEvent parse_fault_request(std::string_view body);

// DELETE /api/v1/faults/{type}: a clear of that fault; `type` must name a fault (404 otherwise).
RuntimeEvent clear_request(std::string_view type);

// POST /api/v1/step body: {"ticks": N} or {"seconds": S} (whole ticks at tick_hz), at least one
// tick and at most max_ticks. Throws HttpError 400.
std::uint64_t parse_step_request(std::string_view body, double tick_hz, std::uint64_t max_ticks);

// {"error": "MESSAGE"} with the message on one line.
std::string error_body(std::string_view message);

}  // namespace swum::emu
