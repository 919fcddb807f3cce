"""The bench's signal names: one table mapping the Modbus input registers and the CAN telemetry
signals (both as decoded from config/) to named, unit-carrying values of one control cycle."""

# name, unit, Modbus input register (physical value), factor, CAN signal (physical), factor
TABLE = [
    ("speed_mm_s", "mm/s", "speed", 1e3, "Speed", 1.0),
    ("position_um", "um", "position", 1e6, "Position", 1e3),
    ("frequency_hz", "Hz", "frequency_output", 1.0, "FrequencyOut", 1.0),
    ("amplitude_vpp", "Vpp", "amplitude_output", 1.0, "AmplitudeOut", 1.0),
    ("phase_deg", "deg", "phase_output", 1.0, "PhaseOut", 1.0),
    ("load_n", "N", "load_output", 1.0, "LoadOut", 1.0),
    ("tip_normal_um", "um", "tip_normal_amplitude", 1.0, "TipNormal", 1.0),
    ("tip_tangential_um", "um", "tip_tangential_amplitude", 1.0, "TipTangential", 1.0),
    ("current_a_ma", "mA", "current_a", 1e3, "CurrentA", 1e3),
    ("current_b_ma", "mA", "current_b", 1e3, "CurrentB", 1e3),
    ("vi_phase_a_deg", "deg", "phase_a", 1.0, "PhaseA", 1.0),
    ("vi_phase_b_deg", "deg", "phase_b", 1.0, "PhaseB", 1.0),
    ("motional_phase_a_deg", "deg", "motional_phase_a", 1.0, "MotionalPhaseA", 1.0),
    ("motional_phase_b_deg", "deg", "motional_phase_b", 1.0, "MotionalPhaseB", 1.0),
    ("power_a_w", "W", "power_a", 1.0, "PowerA", 1.0),
    ("power_b_w", "W", "power_b", 1.0, "PowerB", 1.0),
    ("temperature_c", "degC", "stator_temperature", 1.0, "StatorTemperature", 1.0),
    ("state", "", "state", 1.0, "State", 1.0),
    ("fault_code", "", "fault_code", 1.0, "FaultCode", 1.0),
    ("last_reject", "", "last_reject_reason", 1.0, "LastReject", 1.0),
    ("reject_count", "", "reject_count", 1.0, "RejectCount", 1.0),  # CAN: modulo 256
    ("tick", "", "tick", 1.0, "Tick", 1.0),
]
# What the controller sent in the cycle (from the holding registers it wrote).
COMMAND_TABLE = [
    ("command", "", "command"),
    ("command_frequency_hz", "Hz", "frequency_setpoint"),
    ("command_vpp", "Vpp", "amplitude_setpoint"),
    ("command_phase_deg", "deg", "phase_setpoint"),
]
UNITS = {row[0]: row[1] for row in TABLE}
UNITS.update({row[0]: row[1] for row in COMMAND_TABLE})
UNITS["drive_on"] = ""
NAMES = ["time_s"] + [row[0] for row in TABLE] + ["drive_on"] + [row[0] for row in COMMAND_TABLE]

STATES = {0: "disabled", 1: "enabled", 2: "fault"}
FAULTS = {0: "none", 1: "command_timeout", 2: "numerical", 3: "over_current", 4: "over_temperature"}


def _clean(value):
    # Decoded counts times a scale carry binary noise (0.000551 * 1e3): round to well below
    # every field's resolution so that printed captures read as the wire's counts.
    return round(float(value), 9)


def from_modbus(inputs, tick_hz):
    sample = {name: _clean(inputs[reg] * factor) for name, _, reg, factor, _, _ in TABLE}
    sample["drive_on"] = float((int(inputs["status"]) >> 3) & 1)
    sample["time_s"] = _clean((inputs["tick"] - 1) / tick_hz)
    return sample, inputs["sim_time"]


def from_can(values, tick_hz):
    sample = {name: _clean(values[sig] * factor) for name, _, _, _, sig, factor in TABLE}
    sample["drive_on"] = values["DriveOn"]
    sample["time_s"] = _clean((values["Tick"] - 1) / tick_hz)
    return sample, values["SimTime"]


def add_command(sample, holding):
    for name, _, reg in COMMAND_TABLE:
        sample[name] = _clean(holding[reg])
    return sample
