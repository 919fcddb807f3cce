"""swum-emu as a subprocess: started with its options, ready when its ready line arrives (never
a sleep), its output kept in a log file, stopped by its own pid (SIGTERM, then SIGKILL)."""
import os
import re
import signal
import subprocess
import threading

from .signals import BenchUsageError


class BenchError(RuntimeError):
    """The bench could not do its job (the emulator did not start, a link broke...): the test
    is not a verdict on the controller."""


_READY = re.compile(r"^swum-emu ready (.*)$")


_ENVIRONMENT = re.compile(r"^(swum-emu: )?(Modbus TCP|Modbus RTU|CAN|GPIO|socket|bind|listen)\b", re.I)


def _start_error(status):
    """Which error a start-up exit is. CLI11 refusing an option exits with 100 or more; swum-emu
    refusing a value, its parameter file or a scenario exits 1: a mistake in the test. A
    transport that cannot open (a port in use, no CAN interface) also exits 1, but says so."""
    return BenchUsageError if status >= 100 or status in (1, 2) else BenchError


class Emulator:
    def __init__(self, binary, args, log_path, ready_timeout_s=30.0):
        if not binary or not os.path.isfile(binary) or not os.access(binary, os.X_OK):
            raise BenchUsageError(f"swum-emu binary {binary!r} is not an executable file "
                                  "(--swum-emu or SWUM_EMU)")
        self.log_path = log_path
        self.command = [binary, *[str(a) for a in args]]
        self.fields = {}
        self._ready = threading.Event()
        self._lock = threading.Lock()
        self._log = open(log_path, "w")
        try:
            self._log.write("$ " + " ".join(self.command) + "\n")
            self._log.flush()
            self.process = subprocess.Popen(self.command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                            stderr=subprocess.STDOUT, text=True, bufsize=1)
        except (OSError, ValueError) as e:  # ValueError: a NUL byte in an argument
            self._log.close()
            raise BenchUsageError(f"cannot start swum-emu {binary}: {getattr(e, 'strerror', None) or e}") from e
        self._reader = threading.Thread(target=self._drain, daemon=True)
        self._reader.start()
        try:
            self._wait_ready(ready_timeout_s)
        except BaseException:  # also Ctrl-C while waiting: never leave swum-emu running
            self.stop()
            raise

    def _wait_ready(self, ready_timeout_s):
        log_path = self.log_path
        if not self._ready.wait(ready_timeout_s) or not self.fields:
            try:  # end of output: the process is exiting; take its status before reading why
                status = self.process.wait(5)
            except subprocess.TimeoutExpired:
                status = None
            self._reader.join(5)
            lines = [line.strip() for line in self.log_tail(20).splitlines()
                     if line.strip() and not line.startswith(("$ ", "[bench]", "Run with --help"))]
            why = lines[-1] if lines else "no output"
            self.stop()
            if status is None:
                raise BenchError(f"swum-emu did not become ready: no ready line in {ready_timeout_s:g} s "
                                 f"(last output: {why}; log {log_path})")
            error = BenchError if _ENVIRONMENT.match(why) else _start_error(status)
            raise error(f"swum-emu exited with status {status} before it was ready: {why} "
                                       f"(log {log_path})")

    def _drain(self):
        for line in self.process.stdout:
            with self._lock:
                self._log.write(line)
                self._log.flush()
            m = _READY.match(line.strip())
            if m and not self.fields:
                self.fields = dict(kv.split("=", 1) for kv in m.group(1).split() if "=" in kv)
                self._ready.set()
        self._ready.set()  # end of output: a start-up failure wakes the waiter

    @property
    def pid(self):
        return self.process.pid

    def modbus_endpoint(self):
        """(host, port) from the ready line's modbus=tcp://HOST:PORT."""
        m = re.match(r"tcp://(.+):(\d+)$", self.fields.get("modbus", ""))
        if not m:
            raise BenchError(f"swum-emu's ready line names no Modbus TCP endpoint: {self.fields}")
        return m.group(1), int(m.group(2))

    def running(self):
        return self.process.poll() is None

    def stop(self, timeout_s=10.0):
        """SIGTERM to our own pid, wait; SIGKILL if it does not exit. Returns the exit status."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self._reader.join(5)
        with self._lock:
            if not self._log.closed:
                self._log.write(f"[bench] swum-emu exited with status {self.process.returncode}\n")
                self._log.close()
        return self.process.returncode

    def log_tail(self, lines=40):
        try:
            with open(self.log_path) as f:
                return "".join(f.readlines()[-lines:])
        except OSError:
            return ""
