"""A speed controller written in Python, as a bench runs one in the loop: PI on the drive
amplitude at a fixed frequency (the law of `swum control`, docs/host.md), with a fault reaction.
The examples use it on Modbus and on CAN; broken_examples/ flips its gain and drops its fault
reaction to show what a failing controller test reads like."""
from swum_bench import Command


class SpeedPI:
    def __init__(self, target_mm_s, frequency_hz=40000.0, kp=0.5, ki=50.0, max_amplitude_v=500.0, cycle_s=0.001,
                 holdoff_cycles=10, target=None):
        self.target_mm_s = target_mm_s
        self.target = target  # optional function of time (s) -> mm/s; else the constant target
        self.frequency_hz = frequency_hz
        self.kp, self.ki, self.max_amplitude_v, self.cycle_s = kp, ki, max_amplitude_v, cycle_s
        self.holdoff_cycles = holdoff_cycles
        self.integral = 0.0
        self.off_cycles = 0

    def react_to_fault(self, sample):
        """Drive off at once; after holdoff_cycles, reset the fault (the next cycles re-enable)."""
        self.integral = 0.0
        self.off_cycles += 1
        action = "reset_fault" if self.off_cycles > self.holdoff_cycles else "disable"
        return Command(action=action, frequency_hz=self.frequency_hz, amplitude_v=0.0)

    def cycle(self, sample):
        if sample["state"] == 2:  # fault
            return self.react_to_fault(sample)
        self.off_cycles = 0
        target = self.target(sample["time_s"]) if self.target else self.target_mm_s
        error = target - sample["speed_mm_s"]
        u = self.kp * error + self.integral
        saturated = (u >= self.max_amplitude_v and error > 0) or (u <= 0 and error < 0)
        if not saturated:  # conditional integration: no wind-up at a limit
            self.integral = min(max(self.integral + self.ki * error * self.cycle_s, 0.0), self.max_amplitude_v)
        amplitude_v = min(max(u, 0.0), self.max_amplitude_v)
        action = "keep_alive" if sample["state"] == 1 else "enable"
        return Command(action=action, frequency_hz=self.frequency_hz, amplitude_v=amplitude_v, phase_deg=90.0)
