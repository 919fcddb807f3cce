#!/usr/bin/python3
"""Nothing computed is lost (issue 14, docs/host.md "Killed, interrupted and resumed runs"): the
real `swum` killed with SIGKILL or interrupted with SIGINT, its NAME.partial checked, `--resume`
run; swum-emu over Modbus TCP for the device scenarios.

  killsafe_integration.py model_kill_resume | resume_errors | synth_kill | log_kill_modbus | device_resume_modbus

Every wait polls a file or a process against a deadline; nothing waits a fixed time.
"""
import csv
import io
import os
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "../firmware_sim"))
from emu_harness import Emulator  # noqa: E402

SWUM = os.environ["SWUM_BINARY"]
SOURCE = os.environ["SWUM_SOURCE_DIR"]
CONFIG = "config/li2019.toml"  # relative: the commands run in SWUM_SOURCE_DIR
OUT = tempfile.mkdtemp(prefix="swum-killsafe-")
EMU_ARGS = ["--watchdog-ms", "5000"]  # generous: a shared CI machine can stall the client
# The Modbus link's wall-time limits for swum, generous: under CPU load swum-emu stalls for longer
# than swum's defaults (1 s to connect, 0.5 s per answer) and the run fails on the stall. Hang
# guards only: no wait below ends on them.
LINK = ["--connect-timeout-ms", "60000", "--timeout-ms", "60000"]
MODEL_HEADER = ("amplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status,"
                "current_a_a,current_b_a,phase_a_deg,phase_b_deg,motional_phase_a_deg,motional_phase_b_deg,power_w,"
                "stator_temperature_c,current_rms_a_a,current_rms_b_a,current_peak_a_a,current_peak_b_a,voltage_a_v,"
                "voltage_b_v,power_a_w,power_b_w,apparent_power_a_va,apparent_power_b_va,power_factor_a,"
                "power_factor_b\n")
DEVICE_HEADER = ("amplitude_v,frequency_hz,load_n,time_s,sweep,speed_mm_s,tip_normal_um,tip_tangential_um,"
                 "speed_spread_mm_s,status,current_a_a,current_b_a,phase_a_deg,phase_b_deg,motional_phase_a_deg,"
                 "motional_phase_b_deg,power_w,stator_temperature_c\n")
# Big enough for about a second on two cores (a model point takes ~4 ms of CPU on the scalar
# path, ~0.5 ms in the SIMD lanes of a batch, issue 16), so the kill lands after the first row
# and well before the last.
MODEL_GRID = ["--amplitude-v", "100,150,200,250,300,350,400", "--frequency-hz", "39000:41000:25", "--load", "0,1", "--jobs", "2"]
# The same voltages and loads every 200 Hz (154 points instead of 1134): where a point costs
# far more (the sanitizer build: MODEL_GRID takes ~15 s there, and the test runs it about three
# times), this grid alone already takes the second the race needs. The uninterrupted run
# decides: this grid if it took at least MIN_RUN_S of wall time, else MODEL_GRID (in the Release
# build, where this one takes ~0.3 s: a third of a second more than before). Either way the kill
# and the interrupt land in a run of about a second or more.
SMALL_MODEL_GRID = ["--amplitude-v", "100,150,200,250,300,350,400", "--frequency-hz", "39000:41000:200", "--load", "0,1",
                    "--jobs", "2"]
MIN_RUN_S = 1.0


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def swum(*args, timeout=600):
    r = subprocess.run([SWUM, *args], cwd=SOURCE, capture_output=True, text=True, timeout=timeout)
    return r.returncode, r.stdout, r.stderr


def start(*args):
    return subprocess.Popen([SWUM, *args], cwd=SOURCE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def read(path):
    with open(path) as f:
        return f.read()


def path(name):
    return os.path.join(OUT, name)


def whole_rows(text, header_lines):
    """The complete rows (lines ending in a newline) after the header lines."""
    return text.split("\n")[header_lines:-1]


def wait_for_rows(partial, rows, proc, seconds=300):
    """Polls `partial` until it holds `rows` whole data rows (after its one header line, or two
    with a comment); fails if the process ends first or the deadline passes."""
    deadline = time.monotonic() + seconds
    while True:
        if os.path.exists(partial):
            text = read(partial)
            header_lines = 2 if text.startswith("#") else 1
            if len(whole_rows(text, header_lines)) >= rows:
                check(proc.poll() is None, f"{partial}: the run ended before it could be stopped (grid too small)")
                return
        if proc.poll() is not None:
            out, err = proc.communicate()
            raise AssertionError(f"the run ended (exit {proc.returncode}) before {rows} rows were in {partial}: {err}")
        check(time.monotonic() < deadline, f"{partial}: fewer than {rows} rows after {seconds} s")
        time.sleep(0.005)


def kill(proc, sig):
    os.kill(proc.pid, sig)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, out, err


def kill_between(args, out, first, total, attempts=5, sig=signal.SIGKILL, start_from=None):
    """Runs `swum *args` (writing `out`) and sends it `sig` once OUT.partial holds `first` whole
    rows, `total` being the rows of a whole run; returns (the partial's text, with first..total-1
    rows, and swum's stderr). `start_from`: the partial each attempt starts from (a --resume run).
    Seeing the rows and the signal cannot be one step: a test process stalled for the rest of the
    run (about a second) finds it finished, or all rows written. Such an attempt says nothing about
    swum: it is made again from scratch, at most `attempts` times."""
    partial = out + ".partial"
    stopped = -signal.SIGKILL if sig == signal.SIGKILL else 130  # SIGINT: swum's own exit 130
    for attempt in range(1, attempts + 1):
        if start_from is not None:
            with open(partial, "w") as f:
                f.write(start_from)
        proc = start(*args)
        deadline = time.monotonic() + 300  # a hang guard only
        while proc.poll() is None:
            if os.path.exists(partial) and len(whole_rows(read(partial), 1)) >= first:
                break
            check(time.monotonic() < deadline, f"{partial}: fewer than {first} rows after 300 s")
            time.sleep(0.005)
        if proc.returncode is None:  # not reaped, so its pid is still its own (a zombie at worst)
            status, _, err = kill(proc, sig)
        else:
            status, (_, err) = proc.returncode, proc.communicate()
        if status == stopped:
            check(not os.path.exists(out), f"the final file exists after signal {sig}")
            text = read(partial)
            if len(whole_rows(text, 1)) < total:
                return text, err
        else:
            check(status == 0, f"the run exited {status}, neither {stopped} (stopped by signal {int(sig)}) nor 0 "
                               f"(finished before it): {err}")
        print(f"attempt {attempt}: the run ended before the signal (the test process stalled); again")
        for name in (out, partial):
            if os.path.exists(name):
                os.remove(name)
    raise AssertionError(f"{attempts} runs ended before the signal")


def check_prefix(partial_text, final_text, header_lines, what):
    """`partial_text` is a valid prefix of `final_text`: the same header lines, then whole rows,
    each equal to the final file's row at the same place. Returns the number of rows."""
    check(partial_text.endswith("\n"), f"{what}: the last row is cut short: {partial_text[-80:]!r}")
    final_lines = final_text.split("\n")
    lines = partial_text.split("\n")[:-1]
    check(lines[:header_lines] == final_lines[:header_lines], f"{what}: header {lines[:header_lines]}")
    rows = lines[header_lines:]
    for i, row in enumerate(rows):
        check(row == final_lines[header_lines + i],
              f"{what}: row {i + 1} is {row!r}, the uninterrupted run's {final_lines[header_lines + i]!r}")
    return len(rows)


def one_line_error(status, err, words, what):
    check(status not in (0, None), f"{what}: exit {status}")
    lines = err.strip().split("\n")
    check(len(lines) == 1 and lines[0].startswith("swum: error: "), f"{what}: not a one-line error: {err!r}")
    for word in words:
        check(word in lines[0], f"{what}: {word!r} not in {lines[0]!r}")
    print(f"ok: {what} -> exit {status}: {lines[0]}")


def model_kill_resume():
    reference = path("reference.csv")
    grid = SMALL_MODEL_GRID
    t0 = time.monotonic()
    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--out", reference)
    check(status == 0, f"uninterrupted sweep: exit {status}: {err}")
    elapsed = time.monotonic() - t0
    if elapsed < MIN_RUN_S:  # too quick to kill in the middle reliably: the full grid
        print(f"uninterrupted: {len(whole_rows(read(reference), 1))} points in {elapsed:.1f} s, "
              f"under {MIN_RUN_S} s: the larger grid")
        grid = MODEL_GRID
        t0 = time.monotonic()
        status, _, err = swum("sweep", "--config", CONFIG, *grid, "--out", reference)
        check(status == 0, f"uninterrupted sweep: exit {status}: {err}")
        elapsed = time.monotonic() - t0
    expected = read(reference)
    total = len(whole_rows(expected, 1))
    print(f"uninterrupted: {total} points in {elapsed:.1f} s")
    check(expected.startswith(MODEL_HEADER), "model header")

    # SIGKILL after the first whole row: a valid prefix, no final file.
    out = path("killed.csv")
    partial = out + ".partial"
    text, _ = kill_between(["sweep", "--config", CONFIG, *grid, "--out", out], out, 1, total)
    killed = check_prefix(text, expected, 1, "killed run")
    check(1 <= killed < total, f"{killed} rows after the kill")
    print(f"SIGKILL: {killed} of {total} rows kept, each equal to the uninterrupted run's")

    # --resume, interrupted by SIGINT: exit 130, a message naming --resume, a longer prefix.
    text, err = kill_between(["sweep", "--config", CONFIG, *grid, "--resume", "--out", out], out, killed + 1, total,
                             sig=signal.SIGINT, start_from=text)
    check("--resume" in err and partial in err, f"SIGINT message: {err!r}")
    interrupted = check_prefix(text, expected, 1, "interrupted resume")
    check(killed < interrupted < total, f"{interrupted} rows after the interrupted resume (had {killed})")
    print(f"SIGINT: {interrupted} of {total} rows kept; stderr: {err.strip()}")

    # Kept rows are not computed again: the first row (not the last, which --resume recomputes to
    # check the config) gets a valid but different tip_tangential_um; it must survive.
    lines = read(partial).split("\n")
    cells = lines[1].split(",")
    cells[5] = "0.123456" if cells[5] != "0.123456" else "0.654321"
    marked = ",".join(cells)
    lines[1] = marked
    with open(partial, "w") as f:
        f.write("\n".join(lines))
    # --resume to the end: the uninterrupted file byte for byte (but the marked row), the partial gone.
    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--resume", "--out", out)
    check(status == 0, f"resume: exit {status}: {err}")
    final = read(out).split("\n")
    check(final[1] == marked, f"a kept row was computed again: {final[1]!r}, kept {marked!r}")
    final[1] = expected.split("\n")[1]
    check("\n".join(final) == expected, "the resumed file differs from the uninterrupted one")
    check(not os.path.exists(partial), "the partial is left after the resume completed")
    print("resumed: the kept rows as they were, the rest byte-identical to the uninterrupted run")


def resume_errors():
    grid = ["--amplitude-v", "100", "--frequency-hz", "40000:40200:100"]
    reference = path("small.csv")
    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--out", reference)
    check(status == 0, f"small sweep: exit {status}: {err}")
    expected = read(reference)
    rows = whole_rows(expected, 1)
    check(len(rows) == 3, f"{len(rows)} rows")
    out = path("resumed.csv")
    partial = out + ".partial"

    def with_partial(text, *args, words, what):
        with open(partial, "w") as f:
            f.write(text)
        status, _, err = swum(*args, "--out", out, timeout=120)
        one_line_error(status, err, words, what)
        check(read(partial) == text, f"{what}: the partial was changed by a refused run")
        check(not os.path.exists(out), f"{what}: a final file was written")

    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--resume", "--out", path("none.csv"), timeout=120)
    one_line_error(status, err, ["--resume", "none.csv.partial"], "model --resume without a partial")
    status, _, err = swum("sweep", "--modbus", "tcp://127.0.0.1:1", *grid, "--resume", "--out", path("none.csv"),
                          timeout=120)
    one_line_error(status, err, ["--resume", "none.csv.partial"], "device --resume without a partial")

    two_rows = MODEL_HEADER + rows[0] + "\n" + rows[1] + "\n"
    with_partial(two_rows, "sweep", "--config", CONFIG, "--amplitude-v", "120", "--frequency-hz", "40000:40200:100", "--resume",
                 words=["row 1", "--amplitude-v"], what="--resume over another grid")
    with_partial(two_rows, "sweep", "--config", CONFIG, "--amplitude-v", "100", "--frequency-hz", "40100", "--resume",
                 words=["2 rows", "--frequency-hz"], what="--resume over a smaller grid")
    with_partial(two_rows, "sweep", "--config", CONFIG, *grid, "--drive-phase-deg", "60", "--resume",
                 words=["last row", "--drive-phase-deg"], what="--resume with another --drive-phase-deg")
    with_partial(DEVICE_HEADER, "sweep", "--config", CONFIG, *grid, "--resume",
                 words=["header", "device"], what="model --resume of a device sweep")
    with_partial(two_rows, "sweep", "--modbus", "tcp://127.0.0.1:1", *grid, "--resume",
                 words=["header", "model"], what="device --resume of a model sweep")
    with_partial("x,y\n1,2\n", "sweep", "--config", CONFIG, *grid, "--resume",
                 words=["header"], what="--resume of another file")
    with_partial(two_rows, "sweep", "--config", CONFIG, *grid,
                 words=["--resume", "unfinished"], what="a fresh run over an unfinished one")

    # A row cut short (a write interrupted by a full disk, say) is computed again.
    with open(partial, "w") as f:
        f.write(two_rows + rows[2][:5])
    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--resume", "--out", out)
    check(status == 0 and read(out) == expected, f"resume after a cut row: exit {status}: {err}")
    # A partial holding every row (killed just before the rename) is only renamed.
    with open(partial, "w") as f:
        f.write(expected)
    os.remove(out)
    status, _, err = swum("sweep", "--config", CONFIG, *grid, "--resume", "--out", out)
    check(status == 0 and read(out) == expected and not os.path.exists(partial), f"complete partial: {err}")
    print("ok: a cut-short row is redone, a complete partial is renamed")


def synth_kill():
    points = path("points.csv")
    with open(points, "w") as f:
        f.write("amplitude_v,frequency_hz,load_n\n")
        for amplitude_v in (150, 250, 350):
            for k in range(200):
                f.write(f"{amplitude_v},{39000 + 10 * k},0\n")
    args = ["synth", "--config", CONFIG, "--points", points, "--seed", "5", "--jobs", "2"]
    reference = path("synth_reference.csv")
    t0 = time.monotonic()
    status, _, err = swum(*args, "--out", reference)
    check(status == 0, f"synth: exit {status}: {err}")
    expected = read(reference)
    total = len(whole_rows(expected, 2))
    print(f"uninterrupted synth: {total} rows in {time.monotonic() - t0:.1f} s")
    out = path("synth_killed.csv")
    proc = start(*args, "--out", out)
    wait_for_rows(out + ".partial", 1, proc)
    status, _, _ = kill(proc, signal.SIGKILL)
    check(status == -signal.SIGKILL, f"exit {status} after SIGKILL")
    check(not os.path.exists(out), "the final synth file exists after a kill")
    kept = check_prefix(read(out + ".partial"), expected, 2, "killed synth")
    check(1 <= kept < total, f"{kept} rows kept")
    print(f"SIGKILL: {kept} of {total} synth rows kept, each equal to the uninterrupted run's")


def log_kill_modbus():
    with Emulator("--speedup", "1", *EMU_ARGS) as emu:
        device = f"tcp://{emu.host}:{emu.port}"
        for sig in (signal.SIGKILL, signal.SIGINT):
            out = path(f"log_{sig.name}.csv")
            proc = start("log", "--modbus", device, *LINK, "--duration-s", "120", "--rate-hz", "200", "--out", out)
            wait_for_rows(out + ".partial", 5, proc, seconds=60)
            status, stdout, err = kill(proc, sig)
            if sig == signal.SIGKILL:
                check(status == -signal.SIGKILL and not os.path.exists(out), f"exit {status}; final file written")
                text = read(out + ".partial")
            else:
                # Ctrl-C ends a log: the file is complete up to the stop and gets its name.
                check(status == 130, f"exit {status} after SIGINT: {err}")
                check(os.path.exists(out) and not os.path.exists(out + ".partial"), "log not renamed after Ctrl-C")
                text = read(out)
            check(text.endswith("\n"), f"{sig.name}: a row is cut short")
            rows = list(csv.reader(io.StringIO(text)))
            check(rows[0][:2] == ["host_time_s", "device_time_s"] and len(rows) >= 6, f"{sig.name}: {rows[:2]}")
            for row in rows[1:]:
                check(len(row) == len(rows[0]), f"{sig.name}: row {row} has {len(row)} cells")
                [float(cell) for cell in row if cell != ""]
            print(f"{sig.name}: {len(rows) - 1} whole log rows kept")


def device_resume_modbus():
    # The settle and dwell of the live tests: repeated runs agree within 0.5 % (a 20 ms settle
    # leaves points near the softening peak unsettled: runs differ by up to 16 %).
    grid = ["--amplitude-v", "150,300", "--frequency-hz", "39600:40600:100", "--settle-ms", "60", "--dwell-ms", "30"]
    curve = 11
    with Emulator("--speedup", "1", *EMU_ARGS) as emu:
        device = ["--modbus", f"tcp://{emu.host}:{emu.port}", *LINK]
        out = path("device.csv")
        partial = out + ".partial"
        # Killed during the second curve (300 V): the first curve is kept as it is, the second
        # is measured again from its top frequency.
        before, _ = kill_between(["sweep", *device, *grid, "--out", out], out, curve + 2, 2 * curve)
        check(before.startswith(DEVICE_HEADER) and before.endswith("\n"), "device partial: header or cut row")
        kept = whole_rows(before, 1)
        check(curve + 2 <= len(kept) < 2 * curve, f"{len(kept)} rows at the kill")
        status, _, err = swum("sweep", *device, *grid, "--resume", "--out", out)
        check(status == 0, f"device resume: exit {status}: {err}")
        check(not os.path.exists(partial), "partial left after the resume")
        # The same rows as an uninterrupted run of the same sweep (a device's numbers are never
        # repeated exactly: within the 3 % + 1 mm/s the live tests allow against the model).
        status, _, err = swum("sweep", *device, *grid, "--out", path("device_uninterrupted.csv"))
        check(status == 0, f"uninterrupted device sweep: {err}")
    after = read(out)
    rows = whole_rows(after, 1)
    check(after.startswith(DEVICE_HEADER) and len(rows) == 2 * curve, f"{len(rows)} rows after the resume")
    check(rows[:curve] == kept[:curve], "the completed curve was not kept byte for byte")
    table = list(csv.DictReader(io.StringIO(after)))
    planned = [(v, 40600 - 100 * k) for v in ("150", "300") for k in range(curve)]
    check([(r["amplitude_v"], int(r["frequency_hz"])) for r in table] == planned, "points not in the planned order")
    check([r["sweep"] for r in table] == ["0"] * curve + ["1"] * curve, f"sweep ids {[r['sweep'] for r in table]}")
    check(all(r["status"] == "ok" for r in table), f"statuses {[r['status'] for r in table]}")
    times = [float(r["time_s"]) for r in table]
    check(all(b > a for a, b in zip(times, times[1:])), f"time_s not increasing: {times}")
    # Measured again, not copied: the rows the kill cut off are not in the file (time_s goes on
    # from the last kept row, so the new ones have other times and values).
    check(rows[curve:len(kept)] != kept[curve:], "the interrupted curve's rows were kept, not measured again")
    uninterrupted = list(csv.DictReader(io.StringIO(read(path("device_uninterrupted.csv")))))
    check([(r["amplitude_v"], r["frequency_hz"], r["sweep"], r["status"]) for r in uninterrupted] ==
          [(r["amplitude_v"], r["frequency_hz"], r["sweep"], r["status"]) for r in table], "rows differ from an uninterrupted run")
    worst = 0.0
    for r, u in zip(table, uninterrupted):
        a, b = float(r["speed_mm_s"]), float(u["speed_mm_s"])
        worst = max(worst, abs(a - b) / max(abs(b), 20.0))
        check(abs(a - b) <= 0.03 * abs(b) + 1.0, f"resumed {r} vs uninterrupted {u}")
    print(f"device resume: curve 1 kept ({curve} rows), curve 2 redone from {table[curve]['frequency_hz']} Hz, "
          f"{len(kept) - curve} rows of it dropped; speeds within {100 * worst:.2f} % of an uninterrupted run")


if __name__ == "__main__":
    scenario = sys.argv[1] if len(sys.argv) > 1 else ""
    functions = {f.__name__: f for f in (model_kill_resume, resume_errors, synth_kill, log_kill_modbus,
                                         device_resume_modbus)}
    if scenario not in functions:
        sys.exit(f"usage: {sys.argv[0]} {'|'.join(functions)}")
    functions[scenario]()
    print(f"{scenario}: PASS")
