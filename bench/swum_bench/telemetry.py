"""The bench's signal names: one table mapping the Modbus input registers and the CAN telemetry
signals (both as decoded from config/) to named, unit-carrying values of one control cycle."""

# name, unit, Modbus input register (physical value), factor, CAN signal (physical), factor
TABLE = [
    ("speed_mm_s", "mm/s", "speed", 1e3, "Speed", 1.0),
    ("position_um", "um", "position", 1e6, "Position", 1e3),
    ("frequency_hz", "Hz", "frequency_output", 1.0, "FrequencyOut", 1.0),
    ("amplitude_v", "V", "amplitude_output", 1.0, "AmplitudeOut", 1.0),
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
    ("command_amplitude_v", "V", "amplitude_setpoint"),
    ("command_phase_deg", "deg", "phase_setpoint"),
]
# Over CANopen (docs/canopen.md): the signals the drive's dictionary carries, by object. The
# state, fault_code and drive_on come from the statusword 0x6041 and 0x603F (cia402.py), which
# every TPDO plan maps; the scale of each object comes from the unit in its EDS name.
CANOPEN_TABLE = [
    ("speed_mm_s", 0x606C), ("position_um", 0x6064), ("frequency_hz", 0x2010), ("amplitude_v", 0x2011),
    ("phase_deg", 0x2012), ("current_a_ma", 0x2020), ("current_b_ma", 0x2021), ("vi_phase_a_deg", 0x2022),
    ("vi_phase_b_deg", 0x2023), ("motional_phase_a_deg", 0x2024), ("motional_phase_b_deg", 0x2025),
    ("temperature_c", 0x2027),
]
# What four TPDOs of 64 bits carry besides the statusword and 0x603F (256 bits exactly);
# Bench(canopen_signals=...) chooses others of CANOPEN_TABLE.
CANOPEN_DEFAULT_SIGNALS = ("speed_mm_s", "position_um", "frequency_hz", "amplitude_v", "phase_deg", "current_a_ma",
                           "current_b_ma", "motional_phase_a_deg")
# Signals the dictionary does not carry: the load and the tip amplitudes are the bench's inputs
# and the model's insides, not a drive's; 0x2026 is the power of both phases, not each; rejects
# are a swum-protocol notion (a CANopen write is refused with an SDO abort); the tick is not
# an object (time is counted in SYNCs).
CANOPEN_MISSING = ("load_n", "tip_normal_um", "tip_tangential_um", "power_a_w", "power_b_w", "last_reject",
                   "reject_count", "tick")
# The unit in an EDS object's name -> the bench's unit and the factor to it.
EDS_UNITS = {"um/s": ("mm/s", 1e-3), "um": ("um", 1.0), "mHz": ("Hz", 1e-3), "mV": ("V", 1e-3),
             "0.01 deg": ("deg", 0.01), "mA": ("mA", 1.0), "0.01 degC": ("degC", 0.01)}

UNITS = {row[0]: row[1] for row in TABLE}
UNITS.update({row[0]: row[1] for row in COMMAND_TABLE})
UNITS["drive_on"] = ""
UNITS.update({"statusword": "", "error_code": "", "command_velocity_mm_s": "mm/s"})  # CANopen only
NAMES = (["time_s"] + [row[0] for row in TABLE] + ["drive_on"] + [row[0] for row in COMMAND_TABLE]
         + ["statusword", "error_code", "command_velocity_mm_s"])

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


def canopen_scales(eds, names):
    """{signal name: (object index, factor)} for the chosen signals, the factor from the unit in
    the object's EDS name (0x2011 is the terminal amplitude, the amplitude every table carries)."""
    objects = dict(CANOPEN_TABLE)
    scales = {}
    for name in names:
        entry = eds[objects[name], 0]
        unit, factor = EDS_UNITS[entry.unit]
        if unit != UNITS[name]:
            raise ValueError(f"{entry.where}: unit {entry.unit!r} is not the signal {name}'s {UNITS[name]!r}")
        scales[name] = (entry.index, factor)
    return scales


def from_canopen(values, scales, time_s):
    """A sample of one SYNC's TPDO values ({object index: value}); time_s is counted in SYNCs."""
    from . import cia402
    sample = {name: _clean(values[index] * factor) for name, (index, factor) in scales.items()}
    statusword, error_code = values[0x6041], values[0x603F]
    sample["state"] = float(cia402.bench_state(statusword))
    sample["fault_code"] = float(cia402.fault_code(error_code))
    if "amplitude_v" in sample:  # as the swum protocols' DriveOn: enabled and driving
        sample["drive_on"] = float(sample["state"] == 1 and sample["amplitude_v"] > 0)
    sample["statusword"] = float(statusword)
    sample["error_code"] = float(error_code)
    sample["time_s"] = _clean(time_s)
    return sample


def add_command(sample, holding):
    for name, _, reg in COMMAND_TABLE:
        sample[name] = _clean(holding[reg])
    if "velocity_setpoint" in holding:  # CANopen: the profile velocity target (NaN: open loop)
        sample["command_velocity_mm_s"] = _clean(holding["velocity_setpoint"])
    return sample
