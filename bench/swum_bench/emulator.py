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


class Emulator:
    def __init__(self, binary, args, log_path, ready_timeout_s=30.0):
        if not binary or not os.path.isfile(binary) or not os.access(binary, os.X_OK):
            raise BenchUsageError(f"swum-emu binary {binary!r} is not an executable file "
                                  "(--swum-emu or SWUM_EMU)")
        self.log_path = log_path
        self.command = [binary, *args]
        self.fields = {}
        self._log = open(log_path, "w")
        self._log.write("$ " + " ".join(self.command) + "\n")
        self._log.flush()
        self._ready = threading.Event()
        self._lock = threading.Lock()
        try:
            self.process = subprocess.Popen(self.command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                            stderr=subprocess.STDOUT, text=True, bufsize=1)
        except OSError as e:
            self._log.close()
            raise BenchUsageError(f"cannot start swum-emu {binary}: {e.strerror}") from e
        self._reader = threading.Thread(target=self._drain, daemon=True)
        self._reader.start()
        if not self._ready.wait(ready_timeout_s) or not self.fields:
            try:  # end of output: the process is exiting; take its status before reading why
                status = self.process.wait(5)
            except subprocess.TimeoutExpired:
                status = None
            self._reader.join(5)
            lines = [line for line in self.log_tail(20).splitlines()
                     if line.strip() and not line.startswith(("$ ", "[bench]"))]
            why = lines[-1].strip() if lines else "no output"
            self.stop()
            if status is None:
                raise BenchError(f"swum-emu did not become ready: no ready line in {ready_timeout_s:g} s "
                                 f"(last output: {why}; log {log_path})")
            # Exit 1 before the ready line is swum-emu refusing its options, parameter file or
            # scenario: a mistake in the test (an inject value out of range, a bad config).
            error = BenchUsageError if status in (1, 2) else BenchError
            raise error(f"swum-emu exited with status {status} before it was ready: {why} (log {log_path})")

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
