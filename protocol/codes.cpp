#include "codes.h"

namespace swum::protocol {

const char* to_string(AmpState state) {
  switch (state) {
    case AmpState::disabled: return "disabled";
    case AmpState::enabled: return "enabled";
    case AmpState::fault: return "fault";
  }
  return "?";
}

const char* to_string(FaultCode fault) {
  switch (fault) {
    case FaultCode::none: return "none";
    case FaultCode::command_timeout: return "command timeout";
    case FaultCode::numerical: return "numerical blow-up";
    case FaultCode::over_current: return "over-current";
    case FaultCode::over_temperature: return "over-temperature";
  }
  return "?";
}

const char* identifier(FaultCode fault) {
  switch (fault) {
    case FaultCode::none: return "none";
    case FaultCode::command_timeout: return "command_timeout";
    case FaultCode::numerical: return "numerical";
    case FaultCode::over_current: return "over_current";
    case FaultCode::over_temperature: return "over_temperature";
  }
  return "?";
}

const char* identifier(Reason reason) {
  switch (reason) {
    case Reason::none: return "none";
    case Reason::frequency_out_of_range: return "frequency_out_of_range";
    case Reason::amplitude_out_of_range: return "amplitude_out_of_range";
    case Reason::phase_out_of_range: return "phase_out_of_range";
    case Reason::load_out_of_range: return "load_out_of_range";
    case Reason::slew_out_of_range: return "slew_out_of_range";
    case Reason::unknown_command: return "unknown_command";
    case Reason::bad_checksum: return "bad_checksum";
    case Reason::stale_alive_counter: return "stale_alive_counter";
    case Reason::wrong_length: return "wrong_length";
    case Reason::illegal_address: return "illegal_address";
    case Reason::split_value: return "split_value";
    case Reason::fault_active: return "fault_active";
    case Reason::enable_line_low: return "enable_line_low";
    case Reason::queue_full: return "queue_full";
    case Reason::reserved_bits: return "reserved_bits";
    case Reason::illegal_function: return "illegal_function";
    case Reason::clock_not_external: return "clock_not_external";
  }
  return "?";
}

const char* to_string(Reason reason) {
  switch (reason) {
    case Reason::none: return "none";
    case Reason::frequency_out_of_range: return "frequency out of range";
    case Reason::amplitude_out_of_range: return "amplitude out of range";
    case Reason::phase_out_of_range: return "phase out of range";
    case Reason::load_out_of_range: return "load out of range";
    case Reason::slew_out_of_range: return "slew limit out of range";
    case Reason::unknown_command: return "unknown command";
    case Reason::bad_checksum: return "bad checksum";
    case Reason::stale_alive_counter: return "stale alive counter";
    case Reason::wrong_length: return "wrong length";
    case Reason::illegal_address: return "illegal address";
    case Reason::split_value: return "split 32-bit value";
    case Reason::fault_active: return "fault active";
    case Reason::enable_line_low: return "enable line low";
    case Reason::queue_full: return "queue full";
    case Reason::reserved_bits: return "reserved bits set";
    case Reason::illegal_function: return "illegal function";
    case Reason::clock_not_external: return "clock not external";
  }
  return "?";
}

}  // namespace swum::protocol
