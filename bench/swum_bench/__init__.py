"""swum_bench: pytest test bench for motor controllers against swum-emu in emulated time
(docs/testing-controllers.md)."""
from .assertions import (WaveformAssertionError, assert_fault_within, assert_follows, assert_overshoot,
                         assert_reaches, assert_rise_time, assert_settles, assert_within)
from .bench import Bench, Injection
from .controllers import Command, ExternalController, ReferenceController
from .emulator import BenchError
from .signals import BenchUsageError, Signal

__all__ = ["Bench", "BenchError", "BenchUsageError", "Command", "ExternalController", "Injection",
           "ReferenceController", "Signal", "WaveformAssertionError", "assert_fault_within", "assert_follows",
           "assert_overshoot", "assert_reaches", "assert_rise_time", "assert_settles", "assert_within"]
