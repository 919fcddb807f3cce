#!/usr/bin/python3
"""`swum population` as users run it (docs/population.md): the same study on one process
(two threads, then one) and under `mpirun -np 2` gives byte-identical files and summaries; a
study killed with SIGKILL leaves a valid prefix of the uninterrupted run's file, and a smaller
study's rows are the first rows of a bigger one's.

  population_integration.py mpirun_np2 | kill

Environment: SWUM_BINARY, SWUM_SOURCE_DIR (as the other host integration tests), and for
mpirun_np2 MPIRUN (the mpirun of the MPI the binary was built with). OpenMPI refuses to run as
root unless OMPI_ALLOW_RUN_AS_ROOT and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM are set: they are set for
the mpirun child only (CI runs as root).
"""
import json
import os
import signal
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from killsafe_integration import check, check_prefix, kill, read, wait_for_rows, whole_rows  # noqa: E402

SWUM = os.environ["SWUM_BINARY"]
SOURCE = os.environ["SWUM_SOURCE_DIR"]
OUT = tempfile.mkdtemp(prefix="swum-population-")
# Small enough for a few seconds on two cores: 6 motors x 2 voltages x 17 frequencies. Down to
# 39000 Hz: on the way down (the operating point's curve) the softer motors' 400 V peaks lie
# below 39300 Hz, where a sweep from rest at each point had collapsed earlier.
STUDY = ["--config", "config/li2019.toml", "--spreads", "config/population.toml", "--seed", "5",
         "--amplitude-v", "200,400", "--frequency-hz", "39000:40600:100", "--yield", "0.5"]


def path(name):
    return os.path.join(OUT, name)


def run(command, env=None):
    r = subprocess.run(command, cwd=SOURCE, capture_output=True, text=True, timeout=600, env=env)
    check(r.returncode == 0, f"{' '.join(command)}: exit {r.returncode}: {r.stdout}{r.stderr}")
    return r.stdout


def population(name, *extra, launcher=(), env=None):
    out, summary = path(name + ".csv"), path(name + ".json")
    stdout = run([*launcher, SWUM, "population", *STUDY, "--motors", "6", *extra, "--out", out, "--summary", summary],
                 env)
    return read(out), read(summary), stdout


def mpirun_np2():
    two_threads = population("threads2", "--jobs", "2")
    one_thread = population("threads1", "--jobs", "1")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    mpirun = os.environ.get("MPIRUN", "mpirun")
    ranks = population("np2", "--jobs", "1", launcher=(mpirun, "-np", "2", "--oversubscribe"), env=env)
    csv_text, summary, stdout = two_threads
    rows = whole_rows(csv_text, 1)
    check(len(rows) == 6, f"{len(rows)} rows")
    check([r.split(",")[0] for r in rows] == [str(i) for i in range(6)], "rows in motor order")
    check(json.loads(summary)["motors"] == 6, "summary")
    for name, other in (("--jobs 1", one_thread), ("mpirun -np 2", ranks)):
        check(other[0] == csv_text, f"{name}: the per-motor file differs from the 2-thread run's")
        check(other[1] == summary, f"{name}: the summary differs from the 2-thread run's")
        check(other[2] == stdout, f"{name}: the printed summary differs: {other[2]!r}")
    print(f"ok: 6 motors, byte-identical on 2 threads, 1 thread and mpirun -np 2:\n{stdout}")


def kill_study():
    study = [SWUM, "population", *STUDY, "--motors", "8", "--jobs", "2"]
    reference = path("reference.csv")
    run([*study, "--out", reference])
    expected = read(reference)
    out = path("killed.csv")
    partial = out + ".partial"
    proc = subprocess.Popen([*study, "--out", out], cwd=SOURCE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    wait_for_rows(partial, 1, proc)
    status, _, _ = kill(proc, signal.SIGKILL)
    check(status == -signal.SIGKILL, f"exit {status} after SIGKILL")
    check(not os.path.exists(out), "the final file exists after a kill")
    kept = check_prefix(read(partial), expected, 1, "killed study")
    check(1 <= kept < 8, f"{kept} rows after the kill")
    print(f"ok: SIGKILL: {kept} of 8 motors kept in {partial}, each equal to the uninterrupted run's")
    # Motor i is a function of (seed, i): a smaller study is the bigger one's first rows.
    smaller = path("smaller.csv")
    run([SWUM, "population", *STUDY, "--motors", "3", "--jobs", "2", "--out", smaller])
    check(whole_rows(read(smaller), 1) == whole_rows(expected, 1)[:3], "--motors 3 is not the first 3 rows of 8")
    print("ok: --motors 3 gives the first 3 rows of --motors 8")


if __name__ == "__main__":
    scenarios = {"mpirun_np2": mpirun_np2, "kill": kill_study}
    scenario = sys.argv[1] if len(sys.argv) > 1 else ""
    if scenario not in scenarios:
        sys.exit(f"usage: {sys.argv[0]} {' | '.join(scenarios)}")
    scenarios[scenario]()
