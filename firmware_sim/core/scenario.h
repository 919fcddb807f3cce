// swum-emu's scenarios (docs/scenarios.md): a timeline of load profiles and injected faults in
// emulated seconds, from a TOML file (--scenario) or one event per --inject NAME@T[:k=v,...].
// Pure: text in, validated values out (no clock, no files, no sockets); the emulator core
// applies the events. Every refusal is a ScenarioError whose what() is one line naming the
// file:line (or the --inject text), the event type and what is wrong.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace swum::emu {

// In the order of docs/scenarios.md. The load events and `ambient` set conditions; the others
// from phase_open on are faults, which `clear` ends early.
enum class EventType : std::uint8_t {
  load_step,
  load_ramp,
  load_sine,
  ambient,
  phase_open,
  phase_short,
  over_temperature,
  voltage_sag,
  jam,
  guide_friction,
  preload_loss,
  encoder_stuck,
  encoder_noise,
  speed_frozen,
  speed_bias,
  speed_noise,
  telemetry_silence,
  modbus_drop,
  modbus_delay,
  can_bus_off,
  clear,
};

// The type's name in files and on the command line ("load_step").
[[nodiscard]] const char* to_string(EventType type);
[[nodiscard]] std::optional<EventType> event_type_from_string(std::string_view name);
// A fault: what `clear` may name (phase_open .. can_bus_off).
[[nodiscard]] bool is_fault(EventType type);

enum class Phase : std::uint8_t { A, B };

// The keys of all types; a type reads only its own (docs/scenarios.md), the others keep these
// defaults. duration_s = 0 means "until cleared" (load_sine: until the next load event).
struct EventParameters {
  double load_n = 0.0;                 // load_step
  double to_n = 0.0;                   // load_ramp
  double offset_n = 0.0;               // load_sine
  double amplitude_n = 0.0;            // load_sine
  double frequency_hz = 0.0;           // load_sine
  double duration_s = 0.0;             // load_ramp, load_sine and the faults that last
  double temperature_c = 0.0;          // ambient
  Phase phase = Phase::A;              // phase_open, phase_short
  double factor = 0.0;                 // voltage_sag, guide_friction, preload_loss
  std::optional<double> position_um;   // jam; absent = where the mover is
  double sigma_um = 0.0;               // encoder_noise
  double bias_mm_s = 0.0;              // speed_bias
  double sigma_mm_s = 0.0;             // speed_noise
  std::uint32_t count = 1;             // modbus_drop
  double delay_ms = 0.0;               // modbus_delay
  EventType fault = EventType::clear;  // clear: the fault it ends (always a fault once parsed)
  bool operator==(const EventParameters&) const = default;
};

struct ScenarioEvent {
  double at_s = 0.0;  // emulated seconds from the start, in [0, 1e6]
  EventType type = EventType::load_step;
  EventParameters parameters;
  std::string origin;  // "file.toml:12" (the [[event]] line) or "--inject"
  bool operator==(const ScenarioEvent&) const = default;
};

struct Scenario {
  std::string name;
  std::uint64_t seed = 0;             // for the noise events
  std::vector<ScenarioEvent> events;  // by at_s; equal times keep their file order
};

class ScenarioError : public std::runtime_error {
 public:
  // Control characters of the message are written as \xNN: what() is always one line.
  explicit ScenarioError(const std::string& message);
};

// A scenario file's text; file_name only names it in errors and origins. Empty text = empty
// scenario. Throws ScenarioError (and nothing else, short of std::bad_alloc).
[[nodiscard]] Scenario parse_scenario(std::string_view toml_text, const std::string& file_name);

// One --inject value, "NAME@SECONDS[:key=value,...]" (e.g. "phase_open@0.25:phase=B,duration_s=0.1"),
// with the keys, ranges and defaults of the file. Throws ScenarioError naming "--inject 'TEXT'".
[[nodiscard]] ScenarioEvent parse_injection(std::string_view text);

// One key of an event type as the API lists it (docs/scenarios.md has the same table): its
// name, kind ("number", "integer", "phase", "fault"), range and whether it must be given.
struct EventKey {
  std::string name;
  std::string kind;
  double min = 0.0;
  double max = 0.0;
  bool min_open = false;  // (min, max] instead of [min, max]
  bool required = true;
};
[[nodiscard]] std::vector<EventKey> event_keys(EventType type);

// A key's value given by a program (the HTTP API's JSON): a number or a name ("B", "jam").
struct EventValue {
  enum class Kind : std::uint8_t { integer, floating, name } kind = Kind::floating;
  std::int64_t integer = 0;
  double floating = 0.0;
  std::string name;
};

// An event of `type` at `at_s` from key/value pairs, with the keys, ranges, defaults and
// messages of a scenario file. Throws ScenarioError "TYPE: what is wrong".
[[nodiscard]] ScenarioEvent make_event(EventType type, const std::vector<std::pair<std::string, EventValue>>& values,
                                       double at_s, const std::string& origin);

// One line in the --inject form with every key the type has (optional ones with their value),
// numbers in their shortest exact form: parse_injection(format_event(e)) equals e except origin.
[[nodiscard]] std::string format_event(const ScenarioEvent& event);

}  // namespace swum::emu
