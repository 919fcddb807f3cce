#!/usr/bin/python3
"""swum-emu's GPIO lines on a real gpio-sim chip (guest tier, tools/vm/with-gpio-sim): the enable
input turns the drive off whatever Modbus says, the fault output follows the fault state, the
quadrature outputs count in the direction of motion. The simulated side is driven and read
through the gpio-sim sysfs (pull / value); commands go over Modbus TCP on 127.0.0.1.
Never asserts timing (TCG guest)."""
import os
import sys
import time

from emu_harness import Emulator, deadline

import modbus_integration as mi  # noqa: E402  (shares the pymodbus Controller)

CFG = os.environ.get("SWUM_GPIO_SIM", "/sys/kernel/config/gpio-sim/swum")
ENABLE, FAULT, A, B = 0, 1, 2, 3


def read(path):
    with open(path) as f:
        return f.read().strip()


CHIP = read(f"{CFG}/bank0/chip_name")
SYSFS = f"/sys/devices/platform/{read(f'{CFG}/dev_name')}/{CHIP}"


def pull(offset, up):
    with open(f"{SYSFS}/sim_gpio{offset}/pull", "w") as f:
        f.write("pull-up" if up else "pull-down")


def level(offset):
    return read(f"{SYSFS}/sim_gpio{offset}/value") == "1"


def wait(predicate, what, timeout=60, tick=None):
    expired = deadline(timeout)
    while not predicate():
        assert not expired(), f"timeout: {what}"
        if tick:
            tick()


def quadrature_count(seconds, tick):
    """Decodes A/B by sampling the simulated side (edges are slow with the coarse resolution)."""
    order = {(0, 0): 0, (1, 0): 1, (1, 1): 2, (0, 1): 3}
    last = order[(level(A), level(B))]
    count = errors = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        state = order[(level(A), level(B))]
        step = (state - last) % 4
        if step == 1:
            count += 1
        elif step == 3:
            count -= 1
        elif step == 2:
            errors += 1  # missed an edge: sampling too slow
        last = state
        tick()
    return count, errors


def main():
    pull(ENABLE, True)
    with Emulator("--gpio", f"{CHIP}:enable={ENABLE},fault={FAULT},a={A},b={B}", "--encoder-resolution-um", "1000",
                  "--speedup", "1", "--watchdog-ms", "300") as emu:
        c = mi.Controller(emu)
        keep = lambda: c.command(0)  # noqa: E731
        assert not level(FAULT)
        c.run_at(400, 40000)
        wait(lambda: c.inputs()["status"] & 8, "drive on", tick=keep)
        # Enable line low: drive off whatever the bus says.
        pull(ENABLE, False)
        wait(lambda: c.inputs()["state"] == 0, "disabled by the enable line", tick=keep)
        c.command(1)
        v = c.inputs()
        wait(lambda: c.inputs()["last_reject_reason"] == mi.MAP.reasons["enable_line_low"], "enable refused")
        v = c.inputs()
        assert v["state"] == 0 and v["amplitude_output"] == 0 and not v["status"] & 4, v
        print("enable line low: drive off, enable refused")
        pull(ENABLE, True)
        wait(lambda: c.inputs()["status"] & 4, "enable line high again", tick=keep)
        c.command(1)
        wait(lambda: c.inputs()["status"] & 8, "drive on again", tick=keep)
        # Encoder: + direction, then reversed phase.
        wait(lambda: c.inputs()["speed"] > 0.05, "moving +", tick=keep)
        forward, e1 = quadrature_count(4.0, keep)
        assert c.write(phase_setpoint=-90) == 0
        wait(lambda: c.inputs()["speed"] < -0.05, "moving -", tick=keep)
        backward, e2 = quadrature_count(4.0, keep)
        print(f"encoder: {forward:+d} counts moving +y, {backward:+d} moving -y (sampling misses {e1 + e2})")
        assert forward > 3 and backward < -3, (forward, backward)
        # Fault line follows the fault state (watchdog).
        wait(lambda: c.inputs()["state"] == 2, "watchdog fault")
        wait(lambda: level(FAULT), "fault line high")
        c.command(3)
        wait(lambda: c.inputs()["state"] == 0, "fault reset")
        wait(lambda: not level(FAULT), "fault line low")
        print("fault line follows the fault state")
        c.close()
        assert emu.stop() == 0
    print("PASS gpio")


if __name__ == "__main__":
    main()
