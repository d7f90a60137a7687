#!/usr/bin/env python3
"""The operator panel in a real browser (issue 11 §3): headless Chromium against `hrg-bench serve`
on the simulated station (paced at 4x real time), nothing from a network.

  panel_browser_test.py --case CASE --source-dir SRC --bin-dir BIN --artifacts DIR

flow          type a serial, start; the progress advances, the live plot draws, the outcome shows
              (as session.json has it), the report link opens the session's report; the panel's
              latency (event time stamp to the frame that shows it) is printed and kept.
abort         a longer session aborted mid-capture from the page (confirm once): ABORTED on the
              page and in session.json, the reason names the operator, the table commanded to zero.
two-browsers  one browser starts; a second sees the same live session and cannot start another;
              the first reloads and picks the session up again.
resume        a longer session whose process is killed (kill -9) after its first run: the page
              says it was interrupted and why, Resume continues it to its outcome (as session.json
              has it), run 1 kept as it was.
hostile       a serial with ../, 10 kB of text, control characters (typed into the page and sent
              directly), forged requests (wrong Host, other Origin, not JSON, too large, unknown
              ids, a path out of the sessions folder), a non-local address without a token
              (refused at start) and requests without the token: all refused with a clear message,
              nothing written outside the sessions folder.

Screenshots go to --artifacts/<case>/. Exit codes: 0 passed; 1 failed; 77 a tool missing
(skipped), which is a failure (1) under CI=true or HRGBENCH_STRICT=1.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

sys.dont_write_bytecode = True
kSkip = 77
# Network refused except loopback (the panel): a proxy on a closed port for everything else (the
# loopback is bypassed by default), and no host name resolves.
kChromiumArgs = [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--proxy-server=127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
    "--window-size=1280,1400", "--no-first-run", "--disable-extensions",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--disable-default-apps",
]
kWaitS = 120.0  # anything the page waits for; a busy 2-core machine is slow, never this slow

SHORT = """\
[sequence]
name = "panel-short"
description = "Three short runs for the panel's browser test"
[settle]
rate_tolerance_rad_s = 1e-4
dwell_s = 0.2
poll_period_s = 0.05
[timeouts]
settle_s = 60.0
excite_s = 10.0
run_margin_s = 5.0
[warmup]
min_s = 0.0
window_s = 2.0
max_drift_c = 0.1
timeout_s = 60.0
[drift]
max_temperature_change_rel = 0.01
action = "flag"
[capture]
max_sequence_gaps = 0
max_samples_lost = 0
[defaults]
a = 1.0
free_run_s = FREE_RUN
sample_rate_hz = 100
[[runs]]
omega_rad_s = -1.0
b = -0.4
theta_rad = 0.0
[[runs]]
omega_rad_s = 0.3
b = 0.0
theta_rad = 0.9
[[runs]]
omega_rad_s = 1.0
b = 0.4
theta_rad = 1.8
"""


class Failed(Exception):
    pass


def Check(condition: bool, message: str) -> None:
    if not condition:
        raise Failed(message)


def Strict() -> bool:
    return os.environ.get("CI") == "true" or os.environ.get("HRGBENCH_STRICT") == "1"


def MissingTools() -> list[str]:
    missing = []
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("python3-selenium")
    if not (shutil.which("chromium") or shutil.which("chromium-browser")):
        missing.append("chromium")
    if not shutil.which("chromedriver"):
        missing.append("chromium-driver (chromedriver)")
    return missing


def FreePort() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def StationText(source: Path, shipped: str, offers: str) -> str:
    """A shipped station file with `offers` for its [offers] (the shipped one names files beside
    it in bench_configs/)."""
    station = (source / "bench_configs" / shipped).read_text()
    assert "\n[offers]" in station, f"{shipped} has no [offers]"
    return station[:station.index("\n[offers]")] + "\n" + offers


# What the test stations offer: the short sequence by default, which is not the first by name
# (sequence-long.toml is), so a page that merely selects the first shows the wrong one.
kOffers = """[offers]
sequences = ["sequence-long.toml", "sequence-short.toml", "sequence-endless.toml"]
default_sequence = "sequence-short.toml"
limits = ["limits-example.toml"]
default_limits = "limits-example.toml"
"""


# The operator's steps of a fixture (issue 26 §1): mounting before the warm-up (with a picture),
# taking the units off after the last run.
PROMPTS = """
[[prompts]]
id = "mount"
at = "start"
text = "Mount the four units and close the lid."
image = "pictures/lid.svg"
[[prompts]]
id = "remove"
at = "end"
text = "Open the lid and take the units off."
"""
LID_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="120" height="60">'
           '<rect x="5" y="5" width="110" height="50" fill="#e08a00"/></svg>')


def WriteConfigs(source: Path, folder: Path, shipped: str = "station-sim.toml",
                 offers: str = kOffers, prompts: bool = False) -> Path:
    """The station (paced 4x) and what it offers: sequence-short (3 x 4 s), sequence-long (3 x 40 s,
    for a resume), sequence-endless (3 x 400 s: what abort and two browsers stop; a loaded machine
    took longer than sequence-long's 30 s of wall time to reach the abort, and the session had
    ended as PASS), the example limits."""
    folder.mkdir(parents=True)
    station = StationText(source, shipped, offers)
    station = station.replace("faster_than_real_time = true",
                              "faster_than_real_time = false\ntime_scale = 4.0")
    # The station's own results store, in the test's folder: the panel lists its recent sessions.
    shipped_store = 'url = "sqlite://../build/out/results.sqlite"'
    assert shipped_store in station, "station-sim.toml's [results] url changed"
    station = station.replace(shipped_store, f'url = "sqlite://{folder / "results.sqlite"}"')
    (folder / "station-panel.toml").write_text(station)
    (folder / "sequence-short.toml").write_text(
        SHORT.replace("FREE_RUN", "4.0") + (PROMPTS if prompts else ""))
    if prompts:
        (folder / "pictures").mkdir()
        (folder / "pictures" / "lid.svg").write_text(LID_SVG)
    (folder / "sequence-long.toml").write_text(
        SHORT.replace("FREE_RUN", "40.0").replace("panel-short", "panel-long"))
    (folder / "sequence-endless.toml").write_text(
        SHORT.replace("FREE_RUN", "400.0").replace("panel-short", "panel-endless"))
    shutil.copy(source / "bench_configs" / "limits-example.toml", folder / "limits-example.toml")
    return folder / "station-panel.toml"


class Panel:
    """`hrg-bench serve` on a free loopback port, stopped (SIGINT, as Ctrl-C) at the end."""

    def __init__(self, bin_dir: Path, station: Path, sessions: Path, log: Path,
                 extra: list[str] | None = None, listen_host: str = "127.0.0.1"):
        self.port = FreePort()
        self.base = f"http://127.0.0.1:{self.port}/"
        self.log = log
        command = [str(bin_dir / "hrg-bench"), "serve", "--station", str(station),
                   "--listen", f"{listen_host}:{self.port}", "--sessions", str(sessions)]
        self.process = subprocess.Popen(command + (extra or []), stdout=log.open("w"),
                                        stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise Failed(f"hrg-bench serve exited with {self.process.returncode}: "
                             + log.read_text())
            try:
                with socket.create_connection(("127.0.0.1", self.port), timeout=1):
                    return
            except OSError:
                time.sleep(0.1)
        raise Failed("hrg-bench serve never listened")

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=120)
            except subprocess.TimeoutExpired:
                self.process.kill()


def Request(url: str, method: str = "GET", body: bytes | None = None,
            headers: dict[str, str] | None = None) -> tuple[int, dict]:
    request = urllib.request.Request(url, data=body, method=method, headers=headers or {})
    try:
        with urllib.request.urlopen(request, timeout=30) as response:
            return response.status, json.loads(response.read() or b"{}")
    except urllib.error.HTTPError as error:
        text = error.read()
        try:
            return error.code, json.loads(text)
        except json.JSONDecodeError:
            return error.code, {"raw": text.decode(errors="replace")}


def PostJson(base: str, path: str, payload: object, headers: dict[str, str] | None = None):
    # With the panel's own Origin, as its page (any browser) sends with a POST; a tokenless POST
    # without one is refused.
    origin = base.rstrip("/")
    return Request(base + path, "POST", json.dumps(payload).encode(),
                   {"Content-Type": "application/json", "Origin": origin, **(headers or {})})


class Browser:
    def __init__(self, artifacts: Path):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        options = webdriver.ChromeOptions()
        for arg in kChromiumArgs:
            options.add_argument(arg)
        options.binary_location = shutil.which("chromium") or shutil.which("chromium-browser")
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")),
                                       options=options)
        self.driver.set_page_load_timeout(kWaitS)
        self.artifacts = artifacts
        artifacts.mkdir(parents=True, exist_ok=True)

    def open(self, url: str) -> None:
        self.driver.get(url)
        self.wait(lambda: self.js("return document.body.dataset.stateLoaded") == "true",
                  "the page never loaded its state")

    def js(self, script: str, *args):
        return self.driver.execute_script(script, *args)

    def wait(self, condition, what: str, timeout_s: float = kWaitS):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            value = condition()
            if value:
                return value
            time.sleep(0.05)
        self.shot("timeout")
        raise Failed(f"waited {timeout_s:.0f} s: {what}")

    def text(self, element_id: str) -> str:
        return self.js("return document.getElementById(arguments[0]).textContent", element_id)

    def data(self, element_id: str, key: str):
        return self.js("return document.getElementById(arguments[0]).dataset[arguments[1]]",
                       element_id, key)

    def start(self, serial: str, sequence: str, operator: str = "OP-BROWSER") -> None:
        from selenium.webdriver.common.by import By
        from selenium.webdriver.support.ui import Select

        if operator and not self.js("return document.getElementById('operator').value"):
            self.driver.find_element(By.ID, "operator").send_keys(operator)
        field = self.driver.find_element(By.ID, "serial")
        field.clear()
        field.send_keys(serial)
        select = Select(self.driver.find_element(By.ID, "sequence"))
        for option in select.options:
            if option.text.startswith(sequence):
                select.select_by_visible_text(option.text)
        self.driver.find_element(By.ID, "start").click()

    def click(self, element_id: str) -> None:
        from selenium.webdriver.common.by import By
        self.driver.find_element(By.ID, element_id).click()

    def plot_pixels(self) -> int:
        """Pixels of the live plot that are not blank (the data drawn, not only the axes)."""
        return self.js("""
            const c = document.getElementById('plot');
            const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
            let n = 0;
            for (let i = 3; i < d.length; i += 4) if (d[i] !== 0) ++n;
            return n;""")

    def console_errors(self) -> list[str]:
        return [e["message"] for e in self.driver.get_log("browser") if e["level"] == "SEVERE"]

    def shot(self, name: str) -> None:
        try:
            self.driver.save_screenshot(str(self.artifacts / f"{name}.png"))
        except Exception:  # noqa: BLE001 (a screenshot is evidence, never the failure itself)
            pass

    def quit(self) -> None:
        self.driver.quit()


def SessionJson(sessions: Path, name: str) -> dict:
    return json.loads((sessions / name / "session.json").read_text())


def WaitOutcome(browser: Browser) -> str:
    return browser.wait(lambda: browser.data("outcome", "kind") or None, "no outcome on the page")


def WaitCapture(browser: Browser, run: int = 1) -> None:
    browser.wait(lambda: browser.data("phase", "phase") == "capture"
                 and browser.text("run").startswith(f"{run} of"),
                 f"run {run} never reached its capture")


def CaseFlow(args, tmp: Path, out: Path) -> None:
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    try:
        browser.open(panel.base)
        Check(browser.text("station").startswith("sim-ci"), "the station is not named")
        browser.start("SN-FLOW-1", "panel-short")
        browser.wait(lambda: "started" in browser.text("message"), "no 'started' message: "
                     + browser.text("message"))
        WaitCapture(browser, 1)
        first = int(browser.wait(lambda: browser.data("samples", "samples"), "no samples"))
        browser.wait(lambda: int(browser.data("samples", "samples") or 0) > first
                     or not browser.text("run").startswith("1 of"), "the progress never advanced")
        browser.wait(lambda: int(browser.data("plot", "points") or 0) > 10, "no points plotted")
        browser.wait(lambda: browser.plot_pixels() > 2000, "the live plot never drew its lines")
        browser.shot("live")
        kind = WaitOutcome(browser)
        browser.wait(lambda: browser.js(
            "return !document.getElementById('report-link').hidden"), "no report link")
        browser.shot("outcome")
        name = browser.text("session-name").split(" ")[0]
        record = SessionJson(sessions, name)
        Check(kind == record["outcome"]["kind"],
              f"the page says {kind}, session.json {record['outcome']['kind']}")
        Check(browser.text("outcome-reason") == record["outcome"]["reason"], "reason differs")
        # Issue 26: who ran it, in the record, on the page and in the store.
        Check(record.get("operator") == "OP-BROWSER", f"operator in the record: {record.get('operator')}")
        Check("OP-BROWSER" in browser.text("operator-shown"), "the page does not show the operator")
        Check(browser.js("return document.querySelectorAll('#runs tbody tr').length") == 3,
              "not three run rows")
        # Issue 26: each judged limit drawn as value ± k·u against its guard bands, with the zone
        # session.json records.
        drawn = browser.js("return Array.from(document.querySelectorAll('#bands svg.guard-band'))"
                           ".map((s) => [s.dataset.quantity, s.dataset.zone,"
                           " s.querySelectorAll('line.interval').length])")
        limits = [lim for lim in record["outcome"].get("verdict", {}).get("limits", [])
                  if all(isinstance(lim.get(k), (int, float)) for k in ("value", "min", "max"))]
        Check(len(limits) > 0, "no limit judged to draw")
        expected = [[lim["quantity"], lim["zone"],
                     1 if isinstance(lim.get("interval_min"), (int, float)) else 0]
                    for lim in limits]
        Check(drawn == expected, f"guard-band bars {drawn}, session.json {expected}")
        colour = browser.js("return getComputedStyle(document.getElementById('outcome'))"
                            ".backgroundColor")
        expected = {"PASS": "rgb(26, 138, 42)", "FAIL": "rgb(198, 40, 40)",
                    "ERROR": "rgb(224, 138, 0)"}.get(kind)
        Check(expected is None or colour == expected, f"{kind} shown in {colour}")
        latency = {k: browser.js(f"return document.body.dataset.{k}") for k in
                   ("latencyCount", "latencyMedianMs", "latencyP95Ms", "latencyMaxMs",
                    "latencySlowest")}
        (out / "latency.json").write_text(json.dumps(latency, indent=1))
        print(f"panel latency, event to screen: {latency}")
        Check(int(latency["latencyCount"] or 0) > 20, "too few live events measured")
        # The recent sessions list has it, from the station's results store (issue 11), with its
        # report linked, and the report opens from the page.
        browser.wait(lambda: browser.js(
            "return document.querySelector('#recent tr[data-session=\"' + arguments[0] + '\"]')"
            " !== null", name), "the session is not among the recent sessions")
        source = browser.text("recent-source")
        Check(source.startswith("from sqlite://") and source.endswith("results.sqlite"),
              f"the recent sessions do not come from the store: {source}")
        Check(StoreOperators(tmp / "configs" / "results.sqlite") == ["OP-BROWSER"],
              f"the store's operator: {StoreOperators(tmp / 'configs' / 'results.sqlite')}")
        Check(browser.js(
            "return document.querySelector('#recent tr[data-session=\"' + arguments[0] + '\"] a')"
            " !== null", name), "the recent session has no report link")
        browser.click("report-link")
        browser.wait(lambda: browser.js("return document.readyState") == "complete"
                     and "report/report.html" in browser.driver.current_url, "report not opened")
        browser.wait(lambda: browser.js("return document.getElementById('outcome') && "
                                        "document.getElementById('outcome').dataset.kind"),
                     "the report has no outcome")
        Check(browser.js("return document.getElementById('outcome').dataset.kind") == kind,
              "the report's outcome differs from the panel's")
        browser.shot("report")
        errors = browser.console_errors()  # read once: the browser's log is emptied by reading
        Check(not errors, f"console errors: {errors}")
    finally:
        browser.quit()
        panel.stop()


def StoreOperators(store: Path) -> list[str]:
    """Every session's operator in the station's SQLite results store, by serial."""
    import sqlite3
    with sqlite3.connect(f"file:{store}?mode=ro", uri=True) as db:
        return [row[0] for row in db.execute("SELECT operator FROM session ORDER BY serial")]


def CaseTraps(args, tmp: Path, out: Path) -> None:
    """Issue 26 §1: the station's default sequence selected, also after a reload (the first by name
    is another); no "none" limits on a station that does not offer it, and a start without limits
    refused; no start without an operator; the operator kept across a reload; a session without
    limits (a station that offers it) shown "not judged", never a green PASS; a child that fails
    at its start said on the page."""
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    try:
        browser.open(panel.base)
        for attempt in ("first load", "reload"):
            selected = browser.js("const s = document.getElementById('sequence');"
                                  "return s.options[s.selectedIndex].text")
            Check(selected.startswith("panel-short"), f"{attempt}: the page selects {selected!r}")
            limits = browser.js("return [...document.getElementById('limits').options]"
                                ".map(o => o.text)")
            Check(limits == ["example"], f"{attempt}: limits offered {limits}")
            browser.driver.refresh()
            browser.open(panel.base)
        status, reply = PostJson(panel.base, "api/start", {"serial": "SN-NL", "sequence": 0,
                                                           "limits": None, "operator": "OP-1"})
        Check(status == 400 and "judges every session" in reply.get("error", ""),
              f"a start without limits: {status} {reply}")
        # No operator: refused on the page, nothing started.
        browser.js("document.getElementById('operator').value = ''")
        browser.js("document.getElementById('serial').value = 'SN-NOOP'")
        browser.click("start")
        browser.wait(lambda: "operator id" in browser.text("message"),
                     "no refusal without an operator: " + browser.text("message"))
        status, reply = PostJson(panel.base, "api/start", {"serial": "SN-NOOP", "sequence": 0,
                                                           "limits": 0})
        Check(status == 400 and "operator" in reply.get("error", ""), f"{status} {reply}")
        Check(not any(sessions.iterdir()), "a session folder without an operator")
        # Entered once, kept across a reload (once per shift).
        browser.js("document.getElementById('operator').value = 'OP-SHIFT';"
                   "document.getElementById('operator').dispatchEvent(new Event('change'))")
        browser.driver.refresh()
        browser.open(panel.base)
        Check(browser.js("return document.getElementById('operator').value") == "OP-SHIFT",
              "the operator was not kept across the reload")
        # The plan before Start: warm-up, three runs, the estimate, every limit, the fit checks.
        steps = browser.js("return [...document.querySelectorAll('#plan tbody tr')]"
                           ".map(r => r.dataset.step)")
        Check(steps[:5] == ["warm-up", "run 1", "run 2", "run 3", "estimate"],
              f"the plan: {steps}")
        Check(sum(s.startswith("limit ") for s in steps) > 5 and
              sum(s.startswith("fit ") for s in steps) == 9, f"the plan's checks: {steps}")
        browser.shot("plan")
        # A child that fails at its start: the page says why (the sequence file is gone).
        (tmp / "configs" / "sequence-short.toml").rename(tmp / "configs" / "moved.toml")
        browser.start("SN-GONE", "panel-short")
        browser.wait(lambda: "sequence-short.toml" in browser.text("outcome-reason"),
                     "the start failure never reached the page: "
                     + browser.text("outcome-reason"))
        Check(browser.data("outcome", "kind") == "ERROR", "the failed start is not an ERROR")
        browser.shot("start-failure")
    finally:
        browser.quit()
        panel.stop()
    # A station that offers a session without limits: shown "not judged", never PASS.
    offers = kOffers + "no_limits = true\n"
    station = WriteConfigs(args.source_dir, tmp / "configs-nl", offers=offers)
    panel = Panel(args.bin_dir, station, tmp / "sessions-nl", tmp / "serve-nl.log")
    browser = Browser(out / "no-limits")
    try:
        browser.open(panel.base)
        from selenium.webdriver.support.ui import Select
        from selenium.webdriver.common.by import By
        Select(browser.driver.find_element(By.ID, "limits")).select_by_visible_text("none")
        browser.start("SN-NL-1", "panel-short")
        kind = WaitOutcome(browser)
        browser.shot("not-judged")
        name = browser.text("session-name").split(" ")[0]
        record = SessionJson(tmp / "sessions-nl", name)
        Check(kind == "NOT-JUDGED" or record["outcome"]["kind"] != "PASS",
              f"a session without limits is shown {kind} (the record: {record['outcome']['kind']})")
        Check(browser.text("outcome") != "PASS", "shown as PASS")
        colour = browser.js("return getComputedStyle(document.getElementById('outcome'))"
                            ".backgroundColor")
        Check(colour != "rgb(26, 138, 42)", "a session without limits shown in green")
    finally:
        browser.quit()
        panel.stop()


def CaseFixture(args, tmp: Path, out: Path) -> None:
    """Issue 26 "done when": the four-unit fixture from the panel, end to end: the operator and
    four serials scanned (Enter moves to the next position), each unit's live state, four outcomes
    and reports on the page as the records have them, the operator in every record and in the
    store. Then one position left empty on purpose: three units run."""
    station = WriteConfigs(args.source_dir, tmp / "configs", shipped="station-sim-fixture.toml",
                           prompts=True)
    sessions = tmp / "sessions"
    os.environ["HRGBENCH_CHROMIUM"] = "/bin/false"  # each report's HTML, no PDF: seconds, not minutes
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    try:
        browser.open(panel.base)
        Check(browser.js("return document.getElementById('serial').hidden"),
              "a fixture station shows the one-unit serial field")
        positions = browser.js("return [...document.querySelectorAll('#fixture-serials input')]"
                               ".filter(i => i.id.startsWith('serial-')).map(i => i.id)")
        Check(positions == ["serial-A", "serial-B", "serial-C", "serial-D"],
              f"the serial fields: {positions}")
        # The scanner: the operator's badge, then each unit's label, each scan ending with Enter.
        browser.driver.find_element(By.ID, "operator").send_keys("OP-FIX" + Keys.ENTER)
        Check(browser.js("return document.activeElement.id") == "serial-A",
              "Enter after the operator does not move to position A")
        for position in "ABCD":
            browser.driver.switch_to.active_element.send_keys(f"FX-{position}" + Keys.ENTER)
            expected = "start" if position == "D" else f"serial-{chr(ord(position) + 1)}"
            Check(browser.js("return document.activeElement.id") == expected,
                  f"Enter after position {position} moves to "
                  + browser.js("return document.activeElement.id"))
        browser.click("start")
        browser.wait(lambda: "started" in browser.text("message"),
                     "no 'started' message: " + browser.text("message"))
        # The operator's first step: a dialog over the page, its picture drawn, the plan saying
        # it waits, the table at zero; an answer to another prompt is refused.
        ConfirmPrompt(browser, panel, "mount", "Mount the four units", image=True)
        # Every unit's live state: all four in the same run's capture at once.
        browser.wait(lambda: browser.js(
            "const r = [...document.querySelectorAll('#units tbody tr')];"
            "return r.length === 4 && r.every(x => x.dataset.state === 'capture')"),
            "the four units were never shown capturing")
        browser.shot("live")
        ConfirmPrompt(browser, panel, "remove", "take the units off")
        kind = WaitOutcome(browser)
        browser.wait(lambda: browser.js(
            "return [...document.querySelectorAll('#units tbody tr')]"
            ".every(r => r.dataset.outcome && r.querySelector('a'))"),
            "not every unit has its outcome and report link")
        browser.shot("outcome")
        fixtures = [p for p in sessions.iterdir() if p.name.startswith("fixture")]
        Check(len(fixtures) == 1, f"fixture folders: {fixtures}")
        record = json.loads((fixtures[0] / "fixture.json").read_text())
        for unit in record["units"]:
            row = "#units tr[data-position=\"" + unit["position"] + "\"]"
            shown = browser.js(f"return document.querySelector('{row}').dataset.outcome")
            Check(shown == unit["outcome"]["kind"],
                  f"{unit['position']}: the page says {shown}, fixture.json {unit['outcome']}")
            unit_record = json.loads((fixtures[0] / unit["folder"] / "session.json").read_text())
            Check(unit_record.get("operator") == "OP-FIX",
                  f"{unit['folder']}: operator {unit_record.get('operator')}")
            answered = [(p["id"], p.get("answer"), p.get("by"), p.get("how"))
                        for p in unit_record.get("prompts", [])]
            Check(answered == [("mount", "confirmed", "OP-FIX", "panel"),
                               ("remove", "confirmed", "OP-FIX", "panel")],
                  f"{unit['folder']}: prompts {answered}")
            Check((fixtures[0] / unit["folder"] / "config" / "pictures" / "lid.svg").exists(),
                  f"{unit['folder']}: the prompt's picture is not in the session's config copy")
            # The panel's sessions leave their reports to a job (--report background): the link
            # answers 202 "being written" (and reloads) until the report is there.
            href = browser.js(f"return document.querySelector('{row} a').href")
            deadline = time.monotonic() + kWaitS
            while True:
                with urllib.request.urlopen(href, timeout=30) as response:
                    status, head = response.status, response.read(4000).lower()
                Check(b"<html" in head and status in (200, 202),
                      f"{unit['position']}: the report link does not open ({status})")
                if status == 200:
                    break
                Check(b"being written" in head and time.monotonic() < deadline,
                      f"{unit['position']}: the report was never written")
                time.sleep(0.5)
        Check(StoreOperators(tmp / "configs" / "results.sqlite") == ["OP-FIX"] * 4,
              f"the store: {StoreOperators(tmp / 'configs' / 'results.sqlite')}")
        Check(kind in ("PASS", "FAIL", "ERROR"), f"the fixture's outcome: {kind}")
        steps = browser.js("return Object.fromEntries([...document.querySelectorAll("
                           "'#plan tbody tr')].map(r => [r.dataset.step, r.dataset.status]))")
        Check(all(steps[f"run {k}"] == "complete" for k in (1, 2, 3)), f"the plan: {steps}")
        # A position left empty on purpose: three units; an empty field not ticked is refused.
        for position in "ABD":
            field = browser.driver.find_element(By.ID, f"serial-{position}")
            field.click()
            field.send_keys(f"FY-{position}")
        typed = browser.js("return ['A', 'B', 'D'].map(p => "
                           "document.getElementById('serial-' + p).value)")
        Check(typed == ["FY-A", "FY-B", "FY-D"], f"the serials typed read {typed}")
        browser.click("start")
        browser.wait(lambda: "position C" in browser.text("message"),
                     "an empty position was not questioned: " + browser.text("message"))
        browser.click("empty-C")
        browser.click("start")
        browser.wait(lambda: browser.js(
            "return document.querySelectorAll('#units tbody tr').length === 3"),
            "three units not shown")
        ConfirmPrompt(browser, panel, "mount", "Mount the four units")
        ConfirmPrompt(browser, panel, "remove", "take the units off")
        WaitOutcome(browser)
        browser.wait(lambda: browser.js(
            "return [...document.querySelectorAll('#units tbody tr')]"
            ".every(r => r.dataset.outcome)"), "not every unit ended")
        browser.shot("three")
        errors = browser.console_errors()
        Check(not errors, f"console errors: {errors}")
    finally:
        browser.quit()
        panel.stop()


def ConfirmPrompt(browser: Browser, panel: Panel, prompt_id: str, text: str,
                  image: bool = False) -> None:
    """Waits for the operator prompt `prompt_id` in its dialog and confirms it as the operator the
    page holds; checks what the operator sees while it is open."""
    browser.wait(lambda: browser.js(
        "const d = document.getElementById('prompt-dialog');"
        "return d.open && d.dataset.id === arguments[0]", prompt_id),
        f"the prompt dialog '{prompt_id}' never opened")
    shown = browser.text("prompt-text")
    Check(text in shown, f"prompt '{prompt_id}' says: {shown}")
    if image:
        browser.wait(lambda: browser.js(
            "const i = document.getElementById('prompt-image');"
            "return !i.hidden && i.complete && i.naturalWidth === 120"),
            "the prompt's picture is not drawn")
    browser.wait(lambda: browser.js(
        "const r = document.querySelector('#plan tr[data-step=\"prompt ' + arguments[0] + '\"]');"
        "return r && r.dataset.status === 'open'", prompt_id),
        f"the plan does not show prompt '{prompt_id}' open")
    status, reply = PostJson(panel.base, "api/prompt",
                             {"id": "not-" + prompt_id, "answer": "confirm", "operator": "OP-X"})
    Check(status == 409 and "is not open" in reply.get("error", ""),
          f"an answer to another prompt: {status} {reply}")
    Check(browser.js("return document.getElementById('prompt-operator').value") == "OP-FIX",
          "the dialog does not carry the operator")
    browser.shot("prompt-" + prompt_id)
    browser.click("prompt-confirm")
    browser.wait(lambda: not browser.js("return document.getElementById('prompt-dialog').open"),
                 f"the prompt dialog '{prompt_id}' stayed open after its answer")
    browser.wait(lambda: browser.js(
        "const r = document.querySelector('#plan tr[data-step=\"prompt ' + arguments[0] + '\"]');"
        "return r && r.dataset.status === 'confirmed'", prompt_id),
        f"the plan does not show prompt '{prompt_id}' confirmed")


def CaseAbort(args, tmp: Path, out: Path) -> None:
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    try:
        browser.open(panel.base)
        browser.start("SN-ABORT-1", "panel-endless")
        WaitCapture(browser, 1)
        browser.wait(lambda: int(browser.data("samples", "samples") or 0) > 100,
                     "the capture never got going")
        browser.shot("before-abort")
        browser.click("abort")
        alert = browser.driver.switch_to.alert  # asks once
        Check("aborted by the operator" in alert.text, "the confirmation does not say what happens")
        alert.accept()
        kind = WaitOutcome(browser)
        browser.wait(lambda: browser.js("return document.getElementById('abort').disabled"),
                     "the session never ended")
        browser.shot("aborted")
        Check(kind == "ABORTED", f"the page says {kind}")
        name = browser.text("session-name").split(" ")[0]
        record = SessionJson(sessions, name)
        Check(record["outcome"]["kind"] == "ABORTED", f"session.json says {record['outcome']}")
        Check("aborted by operator" in record["outcome"]["reason"],
              "the record does not say the operator aborted it: "
              + record["outcome"]["reason"])
        Check(record["runs"][0]["status"] == "aborted", "run 1 not recorded as aborted")
        log = browser.text("log")
        Check("abort requested by the operator" in log, "the page does not show the abort")
        Check("table commanded to zero rate" in log, "the table was not commanded to zero: " + log)
        Check("table commanded to zero rate" in (tmp / "serve.log").read_text(),
              "the session's log does not say the table was commanded to zero")
        # Issue 26: the table's rate shown until it reads zero, and the page says so (it froze at
        # the last capture's rate before).
        browser.wait(lambda: browser.data("table-stop", "zero") == "true",
                     "the page never showed the table at zero: " + browser.text("table-stop"))
        Check("reads zero" in browser.text("table-stop"), browser.text("table-stop"))
        Check(abs(float(browser.data("table-stop", "rate"))) < 1e-3,
              "the last rate shown: " + str(browser.data("table-stop", "rate")))
        Check("the table reads zero" in browser.text("log"), "the log does not say it")
    finally:
        browser.quit()
        panel.stop()


def SessionChild(panel_pid: int) -> int:
    """The panel's `hrg-bench run` child (its parent is the panel), or 0."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            argv = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        ppid = int(stat[stat.rindex(")") + 1:].split()[1])
        if ppid == panel_pid and len(argv) > 1 and argv[1] == b"run":
            return int(entry.name)
    return 0


def CaseResume(args, tmp: Path, out: Path) -> None:
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    try:
        browser.open(panel.base)
        browser.wait(lambda: browser.js("return document.getElementById('interrupted-box').hidden"),
                     "an interrupted session shown before any ran")
        browser.start("SN-RESUME-1", "panel-long")
        WaitCapture(browser, 2)  # run 1 complete
        name = browser.text("session-name").split(" ")[0]
        run1 = (sessions / name / "runs" / "run-001.csv").read_bytes()
        child = SessionChild(panel.process.pid)
        Check(child > 0, "no `hrg-bench run` child of the panel")
        os.kill(child, signal.SIGKILL)
        browser.wait(lambda: not browser.js(
            "return document.getElementById('interrupted-box').hidden"),
            "the page never said the session was interrupted")
        reason = browser.text("interrupted-reason")
        browser.shot("interrupted")
        Check(name in reason and "killed by signal 9 (SIGKILL)" in reason,
              "the page does not say which session and why: " + reason)
        Check(SessionJson(sessions, name)["state"] == "running", "the record is not open")
        browser.wait(lambda: browser.data("outcome", "kind") == "INTERRUPTED",
                     "the page does not say the session is interrupted (not ERROR)")
        browser.click("resume")
        browser.wait(lambda: "resumed" in browser.text("session-name"),
                     "the resumed session never showed")
        kind = WaitOutcome(browser)
        browser.shot("resumed")
        record = SessionJson(sessions, name)
        Check(record["state"] == "closed", "the record is not closed after the resume")
        Check(kind == record["outcome"]["kind"],
              f"the page says {kind}, session.json {record['outcome']['kind']}")
        Check(len(record.get("resumed_at", [])) == 1, "resumed_at does not hold the one resume")
        Check((sessions / name / "runs" / "run-001.csv").read_bytes() == run1,
              "run 1 changed in the resume")
        Check(browser.js("return document.getElementById('interrupted-box').hidden"),
              "the page still offers a resume of a closed record")
    finally:
        browser.quit()
        panel.stop()


def CaseTwoBrowsers(args, tmp: Path, out: Path) -> None:
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    first = Browser(out / "first")
    second = None
    try:
        first.open(panel.base)
        first.start("SN-TWO-1", "panel-endless")
        WaitCapture(first, 1)
        second = Browser(out / "second")
        second.open(panel.base)
        second.wait(lambda: second.text("unit") == "SN-TWO-1", "the second browser does not see "
                    "the session")
        second.wait(lambda: int(second.data("plot", "points") or 0) > 0,
                    "the second browser has no live plot")
        before = int(second.data("samples", "samples") or 0)
        second.wait(lambda: int(second.data("samples", "samples") or 0) > before,
                    "the second browser's progress does not advance")
        second.start("SN-TWO-2", "panel-short")
        second.wait(lambda: "already running" in second.text("message"),
                    "the second start was not refused clearly: " + second.text("message"))
        second.shot("refused")
        Check(not any(p.name.startswith("SN-TWO-2") for p in sessions.iterdir()),
              "a folder was made for the refused session")
        # A reload picks the running session up again.
        first.driver.refresh()
        first.wait(lambda: first.text("unit") == "SN-TWO-1", "the reload lost the session")
        first.wait(lambda: int(first.data("plot", "points") or 0) > 0, "no plot after reload")
        first.shot("reloaded")
        second.click("abort")
        second.driver.switch_to.alert.accept()
        Check(WaitOutcome(first) == "ABORTED", "the first browser did not see the abort")
        Check(WaitOutcome(second) == "ABORTED", "the second browser did not see the abort")
    finally:
        first.quit()
        if second:
            second.quit()
        panel.stop()


def Tree(root: Path, skip: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if skip not in p.parents and p != skip}


def CaseHostile(args, tmp: Path, out: Path) -> None:
    station = WriteConfigs(args.source_dir, tmp / "configs")
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    before = Tree(tmp, sessions)
    browser = Browser(out)
    try:
        browser.open(panel.base)
        browser.js("document.getElementById('operator').value = 'OP-HOSTILE'")
        hostile = {
            "dot-dot": ("../../etc/x", "'/'"),
            "10 kB": ("A" * 10240, "too long: 10240 characters"),
            "control characters": ("SN\u0001\u001b[2J", "control character"),
            "dot-dot only": ("..", "must start with a letter or a digit"),
        }
        for label, (serial, expected) in hostile.items():
            browser.js("document.getElementById('serial').value = arguments[0];"
                       "document.getElementById('message').textContent = '';", serial)
            browser.click("start")
            browser.wait(lambda: browser.text("message"), f"{label}: no message")
            Check(expected in browser.text("message"),
                  f"{label}: the page says {browser.text('message')!r}")
            status, reply = PostJson(panel.base, "api/start",
                                     {"serial": serial, "sequence": 0, "limits": None})
            Check(status == 400 and expected in reply.get("error", ""), f"{label}: {status} {reply}")
        browser.shot("refused")
        forged = [
            ("wrong Host", Request(panel.base + "api/state", headers={"Host": "evil.example"}),
             403, "localhost only"),
            ("other Origin", PostJson(panel.base, "api/start", {"serial": "SN1", "sequence": 0},
                                      {"Origin": "http://evil.example"}), 403, "another site"),
            ("not JSON", Request(panel.base + "api/start", "POST", b"serial=SN1",
                                 {"Content-Type": "application/x-www-form-urlencoded",
                                  "Origin": panel.base.rstrip("/")}),
             415, "application/json"),
            ("too large", Request(panel.base + "api/start", "POST", b"{" + b" " * 100000 + b"}",
                                  {"Content-Type": "application/json",
                                   "Origin": panel.base.rstrip("/")}), 413, "too large"),
            ("rebinding Host", PostJson(panel.base, "api/start", {"serial": "SN1", "sequence": 0},
                                        {"Host": f"127.attacker.example:{panel.port}",
                                         "Origin": f"http://127.attacker.example:{panel.port}"}),
             403, "localhost only"),
            ("no Origin", Request(panel.base + "api/abort", "POST", b"{}",
                                  {"Content-Type": "application/json"}), 403, "Origin"),
            ("unknown sequence", PostJson(panel.base, "api/start", {"serial": "SN1", "sequence": 7}),
             400, "allowed sequences"),
            ("a path for a sequence", PostJson(panel.base, "api/start",
                                               {"serial": "SN1", "sequence": "/etc/passwd"}),
             400, "allowed sequences"),
            ("unknown field", PostJson(panel.base, "api/start",
                                       {"serial": "SN1", "sequence": 0, "output": "/tmp/x"}),
             400, "unknown field"),
            ("report outside", Request(panel.base + "sessions/..%2F..%2Fconfigs/report/x.toml"),
             404, ""),
            ("abort without a session", PostJson(panel.base, "api/abort", {}), 409, "no session"),
        ]
        for label, (status, reply), expected_status, expected in forged:
            Check(status == expected_status and expected in json.dumps(reply),
                  f"{label}: {status} {reply}")
        # Another address without a token: refused at start, with the reason.
        result = subprocess.run(
            [str(args.bin_dir / "hrg-bench"), "serve", "--station", str(station), "--listen",
             f"0.0.0.0:{FreePort()}", "--sessions", str(sessions)],
            capture_output=True, text=True, timeout=60)
        Check(result.returncode == 4 and "needs an access token" in result.stderr,
              f"0.0.0.0 without a token: {result.returncode} {result.stderr}")
        # With a token: every request without it (or with a wrong one) is refused.
        token_file = tmp / "configs" / "token"
        token_file.write_text("s3cret-token-0123456789\n")
        guarded = Panel(args.bin_dir, station, sessions, tmp / "serve-token.log",
                        ["--token-file", str(token_file)], listen_host="0.0.0.0")
        try:
            for label, url in [("no token", guarded.base + "api/state"),
                               ("wrong token", guarded.base + "api/state?token=guess")]:
                status, reply = Request(url)
                Check(status == 401 and "access token" in reply.get("error", ""),
                      f"{label}: {status} {reply}")
            status, reply = PostJson(guarded.base, "api/start", {"serial": "SN-T", "sequence": 0})
            Check(status == 401, f"a tokenless start: {status} {reply}")
            status, reply = Request(guarded.base + "api/state?token=s3cret-token-0123456789")
            Check(status == 200 and reply.get("station") == "sim-ci", f"with the token: {status}")
            browser.open(guarded.base + "?token=s3cret-token-0123456789")
            Check(browser.text("station").startswith("sim-ci"), "the page does not work with the "
                  "token")
        finally:
            guarded.stop()
        Check(not any(sessions.iterdir()), f"sessions written: {list(sessions.iterdir())}")
        after = Tree(tmp, sessions) - {"serve-token.log", "configs/token"}
        Check(after == before, f"written outside the sessions folder: {after - before}")
    finally:
        browser.quit()
        panel.stop()


def WaitReportJobs(root: Path, limit_s: float = kWaitS) -> None:
    """The panel's sessions leave their reports to jobs (hrg-bench --report background) that
    outlive the panel: the folder is removed only once none of them still writes into it."""
    deadline = time.monotonic() + limit_s
    for job_file in root.rglob("job.json"):
        try:
            pid = int(json.loads(job_file.read_text()).get("pid", 0))
        except (OSError, ValueError, AttributeError):
            continue
        while pid > 0 and Path(f"/proc/{pid}").exists() and time.monotonic() < deadline:
            time.sleep(0.1)


def CaseAdaptive(args, tmp: Path, out: Path) -> None:
    """Issue 27 §1 on the panel: a sequence with [adaptive] ends once the unit is decided; the plan
    says the runs left are not needed and why, as the record does."""
    offers = kOffers.replace('"sequence-endless.toml"]',
                             '"sequence-endless.toml", "sequence-adaptive.toml"]')
    station = WriteConfigs(args.source_dir, tmp / "configs", offers=offers)
    (tmp / "configs" / "sequence-adaptive.toml").write_text(
        SHORT.replace("FREE_RUN", "4.0").replace("panel-short", "panel-adaptive")
        .replace("[defaults]", "[adaptive]\nstop_when_decided = true\nmin_runs = 2\n[defaults]"))
    sessions = tmp / "sessions"
    panel = Panel(args.bin_dir, station, sessions, tmp / "serve.log")
    browser = Browser(out)
    try:
        browser.open(panel.base)
        browser.start("SN-ADAPT-1", "panel-adaptive")
        kind = WaitOutcome(browser)
        name = browser.text("session-name").split(" ")[0]
        record = SessionJson(sessions, name)
        early = record["outcome"].get("ended_early")
        Check(early is not None and early.get("after_run") == 2 and early.get("planned_runs") == 3,
              f"the record's ended_early: {early} (outcome {kind}: {record['outcome']['reason']})")
        status = {run: browser.js("return document.querySelector('#plan tr[data-step=\"run "
                                  + str(run) + "\"]').dataset.status") for run in (1, 2, 3)}
        Check(status == {1: "complete", 2: "complete", 3: "not needed"},
              f"the plan's runs: {status}")
        note = browser.js("return document.querySelector('#plan tr[data-step=\"run 3\"]')"
                          ".cells[2].textContent")
        Check(f"decided after run 2 of 3: {early['why']}" in note, f"run 3 says {note!r}")
        browser.shot("adaptive")
        errors = browser.console_errors()
        Check(not errors, f"console errors: {errors}")
    finally:
        browser.quit()
        panel.stop()


CASES = {"flow": CaseFlow, "abort": CaseAbort, "two-browsers": CaseTwoBrowsers,
         "hostile": CaseHostile, "resume": CaseResume, "traps": CaseTraps, "fixture": CaseFixture,
         "adaptive": CaseAdaptive}


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--case", required=True, choices=sorted(CASES))
    parser.add_argument("--source-dir", type=Path, required=True)
    parser.add_argument("--bin-dir", type=Path, required=True)
    parser.add_argument("--artifacts", type=Path, required=True)
    args = parser.parse_args()
    missing = MissingTools()
    if missing:
        print("panel_browser: missing " + ", ".join(missing) + " (scripts/setup-debian.sh)")
        return 1 if Strict() else kSkip
    out = args.artifacts / args.case
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    tmp = Path(tempfile.mkdtemp(prefix=f"hrgbench-panel-{args.case}-"))
    try:
        CASES[args.case](args, tmp, out)
    except Failed as failure:
        print(f"panel_browser.{args.case}: FAILED: {failure}")
        for log in tmp.glob("serve*.log"):
            print(f"--- {log.name} (last 40 lines)")
            print("\n".join(log.read_text(errors="replace").splitlines()[-40:]))
        return 1
    finally:
        WaitReportJobs(tmp)
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"panel_browser.{args.case}: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
