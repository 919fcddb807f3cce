#!/usr/bin/env python3
"""swum-emu's dashboard (GET /, firmware_sim/dashboard/) in a real browser: headless Chromium
driven by selenium against the real binary (--http 127.0.0.1:0).

Wall clock: the page goes live, its charts fill (six uPlot canvases with their lines drawn), the
amplifier enabled over Modbus TCP shows as "enabled" with a non-zero speed and currents; a click on
the over_temperature fault button trips the amplifier, seen both on the page (#fault, #fault-code)
and in the Modbus input register fault_code. Around that click the page records (#record-start,
#record-stop): its status counts N rows, its download link appears, and the CSV fetched from that
link has the recording's header, N rows, one per tick, running from "enabled" into the trip.
Lockstep (--clock external): the step box shows and its button advances the emulated time by the
ticks asked for. Token (--http-token): without it the page shows the token box (the API said 401)
and opens no stream; a wrong token is refused in the box, the right one makes the page go live;
a fresh load of /#token=T goes live without the box. On every page: every request went to the
emulator's own origin, and the browser console holds no error (on the page without a token, only
the browser's own lines for the API's 401 answers).

Usage: dashboard_chromium_test.py [--screenshot PATH]   (SWUM_EMU = binary, SWUM_SOURCE_DIR = repo)
Exit 0 on pass; otherwise one line "FAIL: reason" on stderr and exit 1. No fixed sleeps: every
wait polls a condition against a deadline (generous, for a loaded 2-core machine)."""
import argparse
import json
import os
import re
import sys
import time
import types

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    import serial_asyncio  # noqa: F401  (pymodbus.client imports it; only Recommended by Debian)
except ImportError:
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402
from selenium import webdriver  # noqa: E402
from selenium.common.exceptions import TimeoutException, WebDriverException  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402

from emu_harness import Emulator, RegisterMap  # noqa: E402

DEADLINE_S = 30.0  # per wait
POLL_S = 0.1
CHROMEDRIVER = "/usr/bin/chromedriver"
CHROMIUM = "/usr/bin/chromium"
MAP = RegisterMap()
CHARTS = ("speed", "frequency", "current", "phase", "temperature", "lateness")
# The operating point: 300 V at 39.8 kHz, reached by slew-limited ramps from 0 V / 40 kHz
# (above both softening peaks of config/li2019.toml: the motor runs at about 0.5 m/s).
DRIVE_HZ, DRIVE_AMPLITUDE_V = 39800.0, 300.0
TOKEN = "some-token-123"
RECORDING_HEADER = "tick,sim_time_s,state,fault,"
# What Chromium itself writes to the console for each API request answered 401 (the page without
# its token): the browser's line, not the page's; let through on that page only.
REFUSED_LINE = re.compile(r"http://127\.0\.0\.1:\d+/api/v1/\S+ - Failed to load resource: "
                          r"the server responded with a status of 401 \(Unauthorized\)")


class Failure(Exception):
    pass


def wait_for(driver, description, condition, timeout=DEADLINE_S):
    """Polls condition(driver) until it returns a truthy value (returned); Failure on the deadline,
    naming what was awaited and the last value seen (a condition may return (ok, seen))."""
    last = {"seen": None}

    def probe(d):
        result = condition(d)
        if isinstance(result, tuple):
            ok, last["seen"] = result
            return (last["seen"] or True) if ok else False
        last["seen"] = result
        return result

    try:
        return WebDriverWait(driver, timeout, poll_frequency=POLL_S).until(probe)
    except TimeoutException:
        raise Failure(f"{description}: not within {timeout:.0f} s (last seen: {last['seen']!r})") from None


def js(driver, script, *args):
    return driver.execute_script(script, *args)


def js_pair(driver, script):
    """A condition written in the page's JavaScript, returning [ok, seen]."""
    ok, seen = js(driver, script)
    return bool(ok), seen


def dataset(driver):
    return js(driver, "return Object.assign({}, document.body.dataset);")


def text(driver, element_id):
    return driver.find_element(By.ID, element_id).text.strip()


def number(driver, key):
    value = dataset(driver).get(key)
    return int(value) if value is not None and value.isdigit() else None


# Each chart's canvas, and how many of its pixels have its first series' stroke colour (its line
# drawn, not just axes and grid); the colour comes from the page's own uPlot instance ("charts",
# a top-level binding of dashboard.js, visible to this script without a hook).
CANVAS_SCRIPT = """
const out = {};
for (const name of arguments[0]) {
  const canvas = document.querySelector('#chart-' + name + ' canvas');
  if (!canvas) { out[name] = null; continue; }
  const u = charts[name], s = u.series[1].stroke;
  const colour = typeof s === 'function' ? s(u, 1) : s;
  const want = [1, 3, 5].map((i) => parseInt(colour.slice(i, i + 2), 16));
  const px = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
  let line = 0;
  for (let i = 0; i < px.length; i += 4)
    if (px[i + 3] > 200 && Math.abs(px[i] - want[0]) + Math.abs(px[i + 1] - want[1]) + Math.abs(px[i + 2] - want[2]) < 60)
      line += 1;
  const r = canvas.getBoundingClientRect(), p = canvas.closest('.panel').getBoundingClientRect();
  const fit = Math.max(320, document.getElementById('chart-' + name).clientWidth);
  out[name] = {width: r.width, height: r.height, line: line, colour: colour, fit: fit,
               panel: [p.left, p.top, p.right, p.bottom], inside: r.left >= p.left - 1 && r.right <= p.right + 1};
}
return out;
"""


def check_canvases(driver, lines=True):
    """Six charts, each a canvas that fills its panel's width (and stays inside it) with its line
    drawn (unless lines=False), and no two panels overlapping."""
    info = js(driver, CANVAS_SCRIPT, list(CHARTS))
    for name in CHARTS:
        c = info.get(name)
        if c is None:
            return False, f"{name}: no <canvas>"
        if c["width"] < 300 or c["height"] < 150 or not c["inside"] or abs(c["width"] - c["fit"]) > 1:
            return False, (f"{name}: canvas {c['width']:.0f}x{c['height']:.0f} for a {c['fit']:.0f} px wide chart, "
                           f"inside its panel: {c['inside']}")
        if lines and c["line"] < 20:
            return False, f"{name}: {c['line']} pixels of its line colour {c['colour']}"
    panels = [info[n]["panel"] for n in CHARTS]
    for i, a in enumerate(panels):
        for b in panels[i + 1:]:
            if a[0] < b[2] - 1 and b[0] < a[2] - 1 and a[1] < b[3] - 1 and b[1] < a[3] - 1:
                return False, f"chart panels overlap: {a} and {b}"
    return True, {n: info[n]["line"] for n in CHARTS}


def check_clean_page(driver, origin, page):
    """The page stayed on its origin (check_same_origin) and logged no console error; returns
    (requests seen, the console errors: none)."""
    requests = check_same_origin(driver, origin)
    errors = console_errors(driver)
    if errors:
        raise Failure(f"browser console errors ({page}): {errors[:3]}")
    return requests, errors


def check_same_origin(driver, origin):
    """Every request of the page went to origin: the page's own resource timing (finished
    requests: the open telemetry stream is not there yet) and chromedriver's network log (every
    request sent, the stream included). Returns how many requests were seen."""
    names = js(driver, "return performance.getEntriesByType('navigation').concat("
                       "performance.getEntriesByType('resource')).map((e) => e.name);")
    sent = network_requests(driver)
    foreign = [n for n in names + (sent or []) if not n.startswith(origin + "/")]
    if foreign:
        raise Failure(f"the page requested other origins than {origin}: {foreign[:3]}")
    if not any(n.endswith("/uPlot.iife.min.js") for n in names):
        raise Failure(f"uPlot missing from the page's resource timing: {names}")
    if sent is not None and not any("/api/v1/stream" in n for n in sent):
        raise Failure(f"the telemetry stream missing from the network log: {sent}")
    return len(names), (len(sent) if sent is not None else None)


def network_requests(driver):
    """URLs of the requests sent since the last call, from chromedriver's performance log (the
    DevTools Network.requestWillBeSent events); None when this driver cannot give it."""
    try:
        entries = driver.get_log("performance")
    except (WebDriverException, AttributeError):
        return None
    urls = []
    for entry in entries:
        message = json.loads(entry["message"])["message"]
        if message.get("method") == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    return urls


def console_errors(driver):
    """SEVERE browser-console entries since the last call (None: the driver cannot give the log)."""
    try:
        entries = driver.get_log("browser")
    except (WebDriverException, AttributeError):
        return None
    return [e.get("message", "") for e in entries if e.get("level") == "SEVERE"]


def fresh_page(driver):
    """Leaves the page before (its timers and stream stop) and drops the logs of its requests
    and console, so that the next checks see only the next page's."""
    driver.get("about:blank")
    network_requests(driver)
    console_errors(driver)


def displayed(driver, element_id):
    return driver.find_element(By.ID, element_id).is_displayed()


# The recording the page's download link points at, fetched by the page itself (its origin, its
# token if any) and summed up here rather than handed whole to Python (about 300 bytes a tick).
CSV_SCRIPT = """
const [href, done] = arguments;
fetch(href).then(async (r) => {
  const body = await r.text();
  const lines = body.split('\\n');
  const last = lines.pop();  // '' after the final newline
  const columns = lines.length ? lines[0].split(',') : [];
  const at = (name) => columns.indexOf(name);
  const out = {status: r.status, type: r.headers.get('content-type'), bytes: body.length, unterminated: last,
               header: lines[0] || '', rows: lines.length - 1, columns: columns.length, ragged: 0, gaps: 0,
               first_gap: null, first_tick: null, last_tick: null, states: [], faults: [], last: null};
  let previous = null;
  for (let i = 1; i < lines.length; ++i) {
    const f = lines[i].split(',');
    if (f.length !== columns.length) out.ragged += 1;
    const tick = Number(f[at('tick')]);
    if (previous !== null && tick !== previous + 1) {
      out.gaps += 1;
      if (out.first_gap === null) out.first_gap = {row: i, after: previous, tick: tick};
    }
    if (out.first_tick === null) out.first_tick = tick;
    out.last_tick = previous = tick;
    const state = f[at('state')], fault = f[at('fault')];
    if (out.states[out.states.length - 1] !== state) out.states.push(state);  // the runs, in order
    if (out.faults[out.faults.length - 1] !== fault) out.faults.push(fault);
  }
  done(out);
}).catch((e) => done({error: String(e)}));
"""


def start_recording(driver):
    """#record-start, then the status says it records (the page asked GET recording after the
    POST); the download link is hidden while no recording is available."""
    if displayed(driver, "record-download"):
        raise Failure(f"the download link shows before any recording (status {text(driver, 'record-status')!r})")
    driver.find_element(By.ID, "record-start").click()
    wait_for(driver, "#record-status 'recording'",
             lambda d: (text(d, "record-status").startswith("recording"), text(d, "record-status")))


def stop_recording(driver, origin):
    """#record-stop, then 'N rows' (N > 0) and the download link; the CSV behind the link, fetched
    by the page: the recording's header, N rows of as many columns, ticks one apart."""
    driver.find_element(By.ID, "record-stop").click()

    def stopped(d):
        status = text(d, "record-status")
        m = re.match(r"(\d+) rows", status)
        return bool(m and int(m.group(1)) > 0 and displayed(d, "record-download")), status
    status = wait_for(driver, "#record-status 'N rows' (N > 0) and the download link", stopped)
    rows = int(re.match(r"(\d+) rows", status).group(1))
    if status != f"{rows} rows":
        raise Failure(f"the recording's status: {status!r} (ticks dropped or an error)")
    href = driver.find_element(By.ID, "record-download").get_attribute("href")
    if href != origin + "/api/v1/recording.csv":
        raise Failure(f"the download link is {href!r}")
    csv = driver.execute_async_script(CSV_SCRIPT, href)
    if csv.get("error") or csv["status"] != 200:
        raise Failure(f"fetching {href} from the page: {csv}")
    if not csv["header"].startswith(RECORDING_HEADER):
        raise Failure(f"the CSV's header: {csv['header'][:80]!r}")
    if csv["rows"] != rows or csv["ragged"] or csv["unterminated"]:
        raise Failure(f"the CSV has {csv['rows']} rows ({csv['ragged']} not {csv['columns']} columns wide, "
                      f"{csv['unterminated'][:40]!r} after the last newline); the page said {rows}")
    if csv["gaps"] or csv["last_tick"] - csv["first_tick"] != rows - 1:
        raise Failure(f"the CSV's ticks are not one apart: {csv['gaps']} gaps, the first {csv['first_gap']}, "
                      f"ticks {csv['first_tick']}..{csv['last_tick']} in {rows} rows")
    return csv


def modbus_client(emu):
    client = ModbusTcpClient(emu.host, port=emu.port, timeout=10)
    if not client.connect():
        raise Failure(f"cannot connect to Modbus TCP {emu.host}:{emu.port}")
    return client


def enable(client):
    regs = ([1] + MAP.encode("frequency_setpoint", DRIVE_HZ) + MAP.encode("amplitude_setpoint", DRIVE_AMPLITUDE_V)
            + MAP.encode("phase_setpoint", 90.0) + MAP.encode("load_force", 0.0)
            + MAP.encode("frequency_slew", 200.0) + MAP.encode("amplitude_slew", 300.0))
    assert len(regs) == MAP.holding["advance"]["address"]  # registers 0..9: not the lockstep advance
    reply = client.write_registers(0, regs, slave=1)
    if reply.isError():
        raise Failure(f"Modbus enable refused: {reply}")


def modbus_fault_code(client):
    reply = client.read_input_registers(MAP.input["fault_code"]["address"], 1, slave=1)
    return None if reply.isError() else reply.registers[0]


def http_origin(emu):
    m = re.search(r"http=(http://127\.0\.0\.1:\d+)", emu.ready)
    if not m:
        raise Failure(f"no http= in the ready line: {emu.ready.strip()!r}")
    return m.group(1)


def make_driver():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                     "--window-size=1400,1100", "--force-device-scale-factor=1", "--no-first-run",
                     "--disable-background-networking", "--disable-component-update", "--disable-sync",
                     "--disable-default-apps", "--disable-extensions"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(DEADLINE_S)
    driver.set_script_timeout(DEADLINE_S)
    return driver


def run_emulator(body, *args, what):
    """Runs body(emu) against a swum-emu started with args, then stops it by its pid (killed if
    the stop is not reached) and requires a clean exit."""
    with Emulator(*args) as emu:
        try:
            result = body(emu)
        finally:
            rc = emu.stop()
    if rc != 0:
        raise Failure(f"swum-emu ({what}) exited {rc}: {emu.stderr.strip()[-300:]}")
    return result


def wall_clock_page(driver, emu, screenshot, timings):
    origin = http_origin(emu)
    t0 = time.monotonic()
    fresh_page(driver)
    driver.get(origin + "/")
    wait_for(driver, "the connection badge 'live'", lambda d: (text(d, "connection") == "live", text(d, "connection")))
    wait_for(driver, "the fault buttons", lambda d: len(d.find_elements(By.CSS_SELECTOR, "button[data-fault]")) > 0)
    timings["page live"] = time.monotonic() - t0

    client = modbus_client(emu)
    try:
        enable(client)
        t1 = time.monotonic()
        wait_for(driver, "state 'enabled'", lambda d: (text(d, "state") == "enabled", text(d, "state")))
        wait_for(driver, "the drive at 300 V, 39.8 kHz on the page",
                 lambda d: (text(d, "op-amplitude-v") == "300" and text(d, "op-frequency") == "39.800",
                            (text(d, "op-amplitude-v"), text(d, "op-frequency"))))
        # The stream keeps coming: updates and chart points grow (2 s of emulated time at 20 Hz).
        u0, p0 = number(driver, "updates") or 0, number(driver, "points") or 0
        wait_for(driver, "dataset.updates and dataset.points to grow by 40",
                 lambda d: ((number(d, "updates") or 0) >= u0 + 40 and (number(d, "points") or 0) >= p0 + 40,
                            dataset(d)))
        moving = wait_for(driver, "non-zero speed and phase currents in the chart data", lambda d: js_pair(d, """
            const last = (c) => c.filter((v) => v !== null).slice(-1)[0] || 0;
            const speed = last(data.speed[1]), a = last(data.current[1]), b = last(data.current[2]);
            return [Math.abs(speed) > 100 && a > 0.1 && b > 0.1, {speed_mm_s: speed, current_a: a, current_b: b}];"""))
        lines = wait_for(driver, "six uPlot canvases with their lines drawn", check_canvases)
        timings["enabled and moving"] = time.monotonic() - t1

        t2 = time.monotonic()
        start_recording(driver)  # the fault below trips the amplifier within the recording
        before = modbus_fault_code(client)
        if before != 0:
            raise Failure(f"Modbus fault_code is {before} before the click")
        buttons = driver.find_elements(By.CSS_SELECTOR, "button[data-fault='over_temperature']")
        if len(buttons) != 1:
            raise Failure(f"{len(buttons)} buttons with data-fault=over_temperature")
        buttons[0].click()
        # #fault is the amplifier's fault identifier, the same name as the fault type's button.
        wait_for(driver, "#fault 'over_temperature' and #fault-code '4'",
                 lambda d: ((text(d, "fault"), text(d, "fault-code")) == ("over_temperature", "4"),
                            (text(d, "fault"), text(d, "fault-code"), text(d, "fault-message"))))
        wait_for(driver, "Modbus input register fault_code 4",
                 lambda d: (lambda code: (code == 4, code))(modbus_fault_code(client)))
        timings["fault on page and Modbus"] = time.monotonic() - t2
    finally:
        client.close()
    t3 = time.monotonic()
    csv = stop_recording(driver, origin)
    # The recording ran from the moving motor into the trip: it starts enabled with no fault and
    # ends in the fault state with over_temperature.
    if csv["states"][0] != "enabled" or csv["states"][-1] != "fault" or csv["faults"][0] != "none" \
            or csv["faults"][-1] != "over_temperature":
        raise Failure(f"the recording's states {csv['states']} and faults {csv['faults']}: "
                      "not from enabled/none to fault/over_temperature")
    timings["recording"] = time.monotonic() - t3
    wait_for(driver, "state 'fault' and over_temperature in force",
             lambda d: (text(d, "state") == "fault" and "over_temperature" in text(d, "active-faults"),
                        (text(d, "state"), text(d, "active-faults"))))
    message = text(driver, "fault-message")
    if not message.startswith("queued over_temperature"):
        raise Failure(f"fault message after the click: {message!r}")

    # A second of stream after the trip (the drive off, the speed falling) before the picture.
    p1 = number(driver, "points") or 0
    wait_for(driver, "20 more chart points after the fault", lambda d: ((number(d, "points") or 0) >= p1 + 20, dataset(d)))
    wait_for(driver, "the speed back to zero after the trip", lambda d: js_pair(d, """
        const v = data.speed[1].filter((x) => x !== null).slice(-1)[0];
        return [Math.abs(v) < 1, v];"""))
    requests, errors = check_clean_page(driver, origin, "wall clock page")
    if screenshot:
        os.makedirs(os.path.dirname(os.path.abspath(screenshot)), exist_ok=True)
        js(driver, "window.scrollTo(0, 0);")
        if not driver.save_screenshot(screenshot):
            raise Failure(f"cannot save the screenshot to {screenshot}")
    return {"moving": moving, "line_pixels": lines, "requests": requests, "console": errors, "csv": csv}


def lockstep_page(driver, emu, timings):
    origin = http_origin(emu)
    t0 = time.monotonic()
    fresh_page(driver)
    driver.get(origin + "/")
    wait_for(driver, "the connection badge 'live' (lockstep)", lambda d: (text(d, "connection") == "live", text(d, "connection")))
    wait_for(driver, "clock 'external (lockstep)'", lambda d: (text(d, "clock") == "external (lockstep)", text(d, "clock")))
    if not driver.find_element(By.ID, "step-box").is_displayed():
        raise Failure("the step box is hidden with --clock external")
    tick0, points0 = number(driver, "tick"), number(driver, "points") or 0
    if tick0 is None:
        raise Failure(f"no dataset.tick: {dataset(driver)}")
    ticks = int(driver.find_element(By.ID, "step-ticks").get_attribute("value"))
    driver.find_element(By.ID, "step").click()
    wait_for(driver, "dataset.tick to change after 'step'", lambda d: (number(d, "tick") != tick0, dataset(d)))
    tick1 = wait_for(driver, f"dataset.tick to be {tick0} + {ticks}",
                     lambda d: (number(d, "tick") == tick0 + ticks, number(d, "tick")))
    wait_for(driver, "a new chart point after the step", lambda d: ((number(d, "points") or 0) > points0, dataset(d)))
    # Without a step the emulated time stands still: the stream repeats the same tick.
    u0 = number(driver, "updates") or 0
    wait_for(driver, "stream updates while standing still", lambda d: ((number(d, "updates") or 0) >= u0 + 5, dataset(d)))
    if number(driver, "tick") != tick0 + ticks:
        raise Failure(f"the tick moved without a step: {dataset(driver)}")
    # The charts follow the window: one column at 900 px, three again at 1400 px.
    widths = []
    for width in (900, 1400):
        driver.set_window_size(width, 1100)
        wait_for(driver, f"the charts laid out again in a {width} px window", lambda d: check_canvases(d, lines=False))
        widths.append(round(js(driver, "return document.querySelector('#chart-speed canvas').getBoundingClientRect().width;")))
    if not widths[0] > widths[1] + 100:
        raise Failure(f"chart widths at 900 and 1400 px windows: {widths}")
    _, errors = check_clean_page(driver, origin, "lockstep page")
    timings["lockstep step"] = time.monotonic() - t0
    return {"tick": (tick0, tick1), "step_ticks": ticks, "console": errors, "widths": widths}


def token_page(driver, emu, timings):
    """(a) No token: the token box (the API answered 401), no stream and no plot; a wrong token is
    refused in the box; the right one makes the page go live. (b) A fresh load of /#token=T (the
    token the page stored in (a) dropped first) goes live without ever showing the box."""
    origin = http_origin(emu)
    t0 = time.monotonic()
    fresh_page(driver)
    driver.get(origin + "/")
    wait_for(driver, "the token box (the API answered 401)",
             lambda d: (displayed(d, "token-box") and "token" in text(d, "token-error"), text(d, "token-error")))
    # The page asks GET recording every 2 s: once that too shows the 401, the page has had 2 s in
    # which it must not have opened the stream nor plotted anything.
    wait_for(driver, "the periodic recording refresh refused as well",
             lambda d: ("missing token" in text(d, "record-status"), text(d, "record-status")))
    sent = network_requests(driver) or []
    before = {"dataset": dataset(driver), "connection": text(driver, "connection"),
              "buttons": len(driver.find_elements(By.CSS_SELECTOR, "button[data-fault]")),
              "download": displayed(driver, "record-download"),
              "stream": [u for u in sent if "/api/v1/stream" in u]}
    if ("updates" in before["dataset"] or "points" in before["dataset"] or before["connection"] != "connecting…"
            or before["buttons"] or before["download"] or before["stream"]):
        raise Failure(f"the page without its token did more than ask for it: {before}")
    foreign = [u for u in sent if not u.startswith(origin + "/")]
    if foreign:
        raise Failure(f"the page requested other origins than {origin}: {foreign[:3]}")
    refused = console_errors(driver) or []

    field = driver.find_element(By.ID, "token")
    field.send_keys("not-" + TOKEN)
    driver.find_element(By.ID, "token-apply").click()
    wait_for(driver, "the token box again, saying 'wrong token'",
             lambda d: (displayed(d, "token-box") and text(d, "token-error") == "wrong token", text(d, "token-error")))
    field.clear()
    field.send_keys(TOKEN)
    driver.find_element(By.ID, "token-apply").click()
    wait_for(driver, "the page live with the token: badge, 10 updates, fault buttons, the box gone",
             lambda d: (text(d, "connection") == "live" and (number(d, "updates") or 0) >= 10
                        and len(d.find_elements(By.CSS_SELECTOR, "button[data-fault]")) > 0
                        and not displayed(d, "token-box"),
                        (text(d, "connection"), dataset(d), text(d, "token-error"))))
    wait_for(driver, "the recording status without the 401",
             lambda d: (text(d, "record-status") == "0 rows", text(d, "record-status")))
    check_same_origin(driver, origin)
    refused += console_errors(driver) or []
    errors = [e for e in refused if not REFUSED_LINE.fullmatch(e)]
    if errors:
        raise Failure(f"browser console errors (token page, typed token): {errors[:3]}")
    timings["token typed"] = time.monotonic() - t0

    t1 = time.monotonic()
    js(driver, "sessionStorage.clear();")  # else the page would find the token stored, not in its address
    fresh_page(driver)
    driver.get(origin + "/#token=" + TOKEN)
    seen_box = []

    def live_without_box(d):
        if displayed(d, "token-box"):
            seen_box.append(text(d, "token-error"))
        return (text(d, "connection") == "live" and (number(d, "updates") or 0) >= 10
                and len(d.find_elements(By.CSS_SELECTOR, "button[data-fault]")) > 0), (text(d, "connection"), dataset(d))
    wait_for(driver, "the page live from /#token=", live_without_box)
    if seen_box or displayed(driver, "token-box"):
        raise Failure(f"the token box showed with #token= in the address: {seen_box[:1]}")
    stored = js(driver, "return sessionStorage.getItem('swum-token');")
    if stored is not None:
        raise Failure(f"a token stored in the session ({stored!r}): the page did not need its address")
    _, errors = check_clean_page(driver, origin, "token page, #token=")
    timings["token in address"] = time.monotonic() - t1
    return {"refused": len(refused)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--screenshot", metavar="PATH", help="save the dashboard after the fault as a PNG")
    args = parser.parse_args()
    start = time.monotonic()
    timings = {}
    driver = None
    try:
        driver = make_driver()
        timings["browser start"] = time.monotonic() - start
        wall = run_emulator(lambda emu: wall_clock_page(driver, emu, args.screenshot, timings),
                            "--http", "127.0.0.1:0", "--watchdog-ms", "0", what="wall clock")
        lock = run_emulator(lambda emu: lockstep_page(driver, emu, timings),
                            "--clock", "external", "--http", "127.0.0.1:0", "--watchdog-ms", "0", what="lockstep")
        tok = run_emulator(lambda emu: token_page(driver, emu, timings),
                           "--http", "127.0.0.1:0", "--http-token", TOKEN, "--watchdog-ms", "0", what="token")
    except Failure as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # noqa: BLE001  (one line, whatever broke)
        print(f"FAIL: {type(e).__name__}: {str(e).strip().splitlines()[0] if str(e).strip() else ''}", file=sys.stderr)
        return 1
    finally:
        if driver is not None:
            driver.quit()
    m = wall["moving"]
    print(f"wall clock: live, enabled at {m['speed_mm_s']:.0f} mm/s, {m['current_a']:.2f}/{m['current_b']:.2f} A; "
          f"6 charts drawn (line pixels {wall['line_pixels']}); over_temperature on the page and in Modbus "
          f"fault_code 4; requests all same-origin ({wall['requests'][0]} in resource timing, "
          f"{wall['requests'][1]} in the network log)")
    c = wall["csv"]
    print(f"recording from the page: {c['rows']} rows, ticks {c['first_tick']}..{c['last_tick']} one apart, "
          f"{c['columns']} columns, {c['bytes']} bytes ({c['type']}), states {' -> '.join(c['states'])}, "
          f"faults {' -> '.join(c['faults'])}")
    print(f"lockstep: step of {lock['step_ticks']} ticks: tick {lock['tick'][0]} -> {lock['tick'][1]}, "
          f"standing still otherwise; chart width {lock['widths'][0]} px in a 900 px window, "
          f"{lock['widths'][1]} px in 1400 px")
    print(f"token: box shown on 401 ({tok['refused']} console lines of the browser's for the 401s), no stream; "
          "wrong token refused; typed token live; /#token= live without the box")
    print("console: " + ("not available from this chromedriver/selenium (check skipped)" if wall["console"] is None
                         else "no errors"))
    print("timings: " + ", ".join(f"{k} {v:.1f} s" for k, v in timings.items())
          + f"; total {time.monotonic() - start:.1f} s" + (f"; screenshot {args.screenshot}" if args.screenshot else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
