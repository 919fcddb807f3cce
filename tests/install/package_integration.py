#!/usr/bin/python3
"""The project as a user's CI uses it (docs/install.md): builds the Debian packages with cpack,
checks them with lintian (no error; the warnings are the ones docs/install.md lists), installs
them, and from a folder outside the checkout, with no path into it (PATH, and the installed
Python package), runs swum and swum-emu (--version; swum-emu without --config on the installed
default motor; `swum pick --config` on the installed motor), a ten-line controller test with
plain `pytest`, and `man swum`; then uninstalls and checks that nothing is left. The same
controller test runs once more with the bench installed by `pip install ./bench`.

  SWUM_PACKAGE_TEST_INSTALL=system   (in the build's configure environment) dpkg -i / dpkg --purge into
                                     this system, the test alone (CI: tools/test sets
                                     it when it runs as root on a throw-away clone); refuses
                                     when swum-hil is already installed
  otherwise                          dpkg-deb -x into a temporary root (PATH and PYTHONPATH point
                                     there); the uninstall check needs the system mode
Environment (from ctest): SWUM_BUILD_DIR (the build to package), SWUM_SOURCE_DIR (the checkout,
only to prove nothing reaches into it)."""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib

BUILD = os.environ["SWUM_BUILD_DIR"]
SOURCE = os.path.realpath(os.environ["SWUM_SOURCE_DIR"])
SYSTEM = os.environ.get("SWUM_PACKAGE_TEST_INSTALL") == "system"
PACKAGES = ("swum-hil", "python3-swum-bench")
# lintian warnings accepted, each with its reason in docs/install.md ("The Debian packages").
ACCEPTED_WARNINGS = {"initial-upload-closes-no-bugs"}

# The user's test: an open-loop controller, ten lines, nothing but the installed plugin.
USER_TEST = '''from swum_bench import Command, assert_within


class OpenLoop:
    def cycle(self, sample):
        return Command(action="enable", frequency_hz=40000, amplitude_v=300)


def test_the_motor_runs(swum_bench):
    bench = swum_bench(OpenLoop())
    bench.step(0.3)
    assert_within(bench.signal("speed_mm_s"), 50, 2000, start_s=0.2)
'''


def check(condition, message):
    if not condition:
        print("FAIL:", message)
        sys.exit(1)


def run(args, **kwargs):
    r = subprocess.run(args, capture_output=True, text=True, timeout=300, **kwargs)
    return r


def project_version():
    with open(os.path.join(SOURCE, "CMakeLists.txt")) as f:
        m = re.search(r"project\(\s*\S+\s+VERSION\s+(\d+\.\d+\.\d+)", f.read())
    check(m, "no project(... VERSION x.y.z) in CMakeLists.txt")
    return m.group(1)


def build_packages(out):
    r = run(["cpack", "--config", os.path.join(BUILD, "CPackConfig.cmake"), "-B", out])
    check(r.returncode == 0, f"cpack failed ({r.returncode}): {r.stdout[-2000:]}{r.stderr[-2000:]}")
    debs = {p: glob.glob(os.path.join(out, f"{p}_*.deb")) for p in PACKAGES}
    check(all(len(v) == 1 for v in debs.values()), f"packages made: {os.listdir(out)}")
    return {p: v[0] for p, v in debs.items()}


def lintian(debs):
    r = run(["lintian", "--fail-on", "error", "--no-tag-display-limit", *debs.values()])
    tags = re.findall(r"^([EWIP]): \S+: (\S+)", r.stdout, re.M)
    print(r.stdout.strip())
    check(r.returncode == 0 and not any(level == "E" for level, _ in tags), f"lintian reports errors: {r.stdout}{r.stderr}")
    warnings = {tag for level, tag in tags if level == "W"}
    check(warnings <= ACCEPTED_WARNINGS, f"lintian warnings not listed in docs/install.md: {warnings - ACCEPTED_WARNINGS}")


def package_files(deb):
    """The paths a package holds (dpkg-deb -c), as absolute paths below /."""
    r = run(["dpkg-deb", "-c", deb])
    check(r.returncode == 0, f"dpkg-deb -c {deb}: {r.stderr}")
    return [line.split(None, 5)[5].split(" -> ")[0][1:].rstrip("/") or "/" for line in r.stdout.splitlines()]


def user_environment(home, root=None):
    """What a user's CI has: PATH (the installation's bin first), HOME, a locale; no SWUM_*."""
    env = {"HOME": home, "LANG": "C.UTF-8", "PATH": "/usr/bin:/bin"}
    if root:
        env["PATH"] = os.path.join(root, "usr", "bin") + ":" + env["PATH"]
        env["PYTHONPATH"] = os.path.join(root, "usr", "lib", "python3", "dist-packages")
        env["MANPATH"] = os.path.join(root, "usr", "share", "man")
    for value in env.values():
        check(SOURCE not in value, f"the user's environment reaches into the checkout: {value}")
    return env


def use_it(work, env, data_dir, version):
    """What a user does with the installation, from `work` (outside the checkout)."""
    for program in ("swum", "swum-emu"):
        r = run([program, "--version"], cwd=work, env=env)
        check(r.returncode == 0 and r.stdout.startswith(f"{program} {version}"), f"{program} --version: {r.stdout}{r.stderr}")
        check(shutil.which(program, path=env["PATH"]) and SOURCE not in shutil.which(program, path=env["PATH"]),
              f"{program} is not the installed one")
    default = os.path.join(data_dir, "li2019.toml")
    # swum-emu without --config: the installed default motor, said on its ready line.
    r = run(["swum-emu", "--modbus", "tcp://127.0.0.1:0", "--duration-s", "0.05", "--speedup", "0"], cwd=work, env=env)
    check(r.returncode == 0, f"swum-emu without --config: {r.returncode}: {r.stderr}")
    ready = next((line for line in r.stdout.splitlines() if line.startswith("swum-emu ready")), "")
    check(f" default_config={default}" in ready, f"the ready line does not name the installed default motor: {ready!r}")
    r = run(["swum", "pick", "--config", default, "--amplitude-v", "300"], cwd=work, env=env)
    check(r.returncode == 0 and re.search(r"\d{5}(\.\d+)? Hz", r.stdout), f"swum pick: {r.returncode}: {r.stdout}{r.stderr}")
    print("swum pick on the installed motor:", r.stdout.strip().splitlines()[0])
    controller_test(work, env, "the package")
    r = run(["man", "-P", "cat", "swum"], cwd=work, env=env)
    check(r.returncode == 0 and "swum - ultrasonic motor model" in r.stdout, f"man swum: {r.returncode}: {r.stderr}")


def controller_test(work, env, how):
    with open(os.path.join(work, "test_my_controller.py"), "w") as f:
        f.write(USER_TEST)
    r = run(["pytest", "-q", "-p", "no:cacheprovider", "test_my_controller.py"], cwd=work, env=env)
    check(r.returncode == 0 and "1 passed" in r.stdout, f"plain pytest with the bench from {how}: {r.stdout[-3000:]}{r.stderr[-2000:]}")
    print(f"pytest with the bench from {how}: {r.stdout.strip().splitlines()[-1]}")


def pip_install(tmp, work, env, version):
    """pip install ./bench (no index: pip builds the local folder with Debian's setuptools)."""
    with open(os.path.join(SOURCE, "bench", "pyproject.toml"), "rb") as f:
        check(tomllib.load(f)["project"]["version"] == version, "bench/pyproject.toml's version is not project(VERSION)")
    target = os.path.join(tmp, "pip")
    source = os.path.join(tmp, "bench-source")  # a copy: pip builds in place and would write into the checkout
    shutil.copytree(os.path.join(SOURCE, "bench"), source, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build"))
    r = run([sys.executable, "-m", "pip", "install", "--quiet", "--no-index", "--no-build-isolation", "--no-deps",
             "--target", target, source], env={**env, "PIP_DISABLE_PIP_VERSION_CHECK": "1"})
    check(r.returncode == 0, f"pip install ./bench: {r.stdout}{r.stderr}")
    pip_env = {**env, "PYTHONPATH": target}
    controller_test(work, pip_env, "pip install ./bench")


def main():
    tmp = tempfile.mkdtemp(prefix="swum-package-")
    try:
        run_all(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)  # also after a failure: its messages say what went wrong


def run_all(tmp):
    version = project_version()
    work, home = os.path.join(tmp, "user-project"), os.path.join(tmp, "home")
    os.makedirs(work)
    os.makedirs(home)
    debs = build_packages(os.path.join(tmp, "debs"))
    lintian(debs)
    files = [path for deb in debs.values() for path in package_files(deb)]
    if SYSTEM:
        for p in PACKAGES:
            r = run(["dpkg-query", "-W", "-f", "${Status}", p])
            check("installed" not in r.stdout.split(), f"{p} is already installed here: this test installs and removes "
                  "only what it installed itself (remove it, or configure the build without SWUM_PACKAGE_TEST_INSTALL=system)")
        existed = {path for path in files if os.path.lexists(path)}
        r = run(["dpkg", "-i", *debs.values()])
        check(r.returncode == 0, f"dpkg -i: {r.stdout}{r.stderr}")
        try:
            env = user_environment(home)
            use_it(work, env, "/usr/share/swum-hil", version)
            # The packaged plugin out of the way first: its entry point would load the plugin even
            # if pip's install had no working metadata of its own.
            r = run(["dpkg", "--purge", "python3-swum-bench"])
            check(r.returncode == 0, f"dpkg --purge python3-swum-bench: {r.stdout}{r.stderr}")
            pip_install(tmp, work, env, version)
        finally:
            r = run(["dpkg", "--purge", *reversed(PACKAGES)])
        check(r.returncode == 0, f"dpkg --purge: {r.stdout}{r.stderr}")
        left = sorted(path for path in files if os.path.lexists(path) and path not in existed)
        check(not left, f"left behind after dpkg --purge: {left[:20]}")
        print(f"uninstalled: none of the {len(files)} paths the packages held is left")
    else:
        root = os.path.join(tmp, "root")
        for deb in debs.values():
            r = run(["dpkg-deb", "-x", deb, root])
            check(r.returncode == 0, f"dpkg-deb -x {deb}: {r.stderr}")
        env = user_environment(home, root)
        use_it(work, env, os.path.join(root, "usr", "share", "swum-hil"), version)
        pip_install(tmp, work, env, version)
        print("(the uninstall check runs with SWUM_PACKAGE_TEST_INSTALL=system)")
    print("package: PASS")


if __name__ == "__main__":
    main()
