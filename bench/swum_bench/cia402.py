"""CiA 402's power state machine as the bench drives it (IEC 61800-7-201 6.3; docs/canopen.md,
"State machine"): the state a statusword shows, the bench's state signal of it, and the
controlword that carries a bench command (enable, disable, reset fault, keep-alive) from the
state the drive was last seen in."""

# Statusword bits 0-3, 5 and 6 code the state (CiA 402 Table 30; bit 5 only where it matters).
STATES = [
    ("not ready to switch on", 0x4F, 0x00),
    ("switch on disabled", 0x4F, 0x40),
    ("ready to switch on", 0x6F, 0x21),
    ("switched on", 0x6F, 0x23),
    ("operation enabled", 0x6F, 0x27),
    ("quick stop active", 0x6F, 0x07),
    ("fault reaction active", 0x4F, 0x0F),
    ("fault", 0x4F, 0x08),
]
# Controlword commands (CiA 402 Table 28, bits 7 and 3-0).
SHUTDOWN = 0x06          # transitions 2, 6, 8: -> ready to switch on (the amplifier off)
ENABLE_OPERATION = 0x0F  # from ready to switch on: switch on + enable operation (3 + 4)
FAULT_RESET = 0x80       # its rising edge: fault -> switch on disabled (15)
# The bench's `command` signal (the Modbus action codes) of the controlword sent.
ACTION_OF_CONTROLWORD = {ENABLE_OPERATION: 1, SHUTDOWN: 2, FAULT_RESET: 3}
# 0x603F -> the swum fault code of docs/protocols.md (docs/canopen.md, "Faults and EMCY codes");
# a CiA 402 error code with no swum fault (0x8130 heartbeat lost) reads -1.
FAULT_CODE_OF_ERROR = {0x0000: 0, 0x8100: 1, 0x6100: 2, 0x2320: 3, 0x4310: 4}
# The bench's state signal: 0 disabled, 1 enabled (the amplifier driven), 2 fault.
BENCH_STATE = {"operation enabled": 1, "quick stop active": 1, "fault reaction active": 2, "fault": 2}


def state_of(statusword):
    for name, mask, value in STATES:
        if statusword & mask == value:
            return name
    return "no CiA 402 state"


def bench_state(statusword):
    return BENCH_STATE.get(state_of(statusword), 0)


def fault_code(error_code):
    return FAULT_CODE_OF_ERROR.get(error_code, -1)


class Sequencer:
    """Turns the bench's commands into controlwords. The bench's `disabled` is CiA 402's ready to
    switch on (0x06), from where one 0x0F enables in one tick (3 + 4); from switch on disabled
    (at the start, after a fault reset) only 0x06 acts, so an enable sends 0x06 first and 0x0F
    in the next cycle. As on the swum CAN link, a keep-alive repeats what the bench last asked
    for, not what the (one cycle old) statusword shows, except in fault, where it is disabled;
    after a fault reset the drive is disabled until enabled again."""

    def __init__(self, first_controlword=SHUTDOWN):
        self.enabled = False
        self.last = first_controlword  # what the drive holds (the configuration wrote it)

    def controlword(self, action, last_statusword):
        state = state_of(last_statusword) if last_statusword is not None else "switch on disabled"
        if action == "reset_fault":
            self.enabled = False
            word = FAULT_RESET
        else:
            if action == "enable":
                self.enabled = True
            elif action == "disable" or (action == "keep_alive" and bench_state(last_statusword or 0) == 2):
                self.enabled = False
            word = SHUTDOWN
            if self.enabled and not (state in ("switch on disabled", "not ready to switch on")
                                     and self.last != SHUTDOWN):
                word = ENABLE_OPERATION
        self.last = word
        return word
