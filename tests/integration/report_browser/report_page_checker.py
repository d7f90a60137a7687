"""The session report as a browser shows it, checked against the report's HTML contract.

The contract (issue 9; hrg-report's header in src/report states it, this checker tests it):
  - every chart is <canvas data-figure="NAME"> inside a <figure> with a <figcaption>; the names are
    channels-run-N, residuals-run-N, orbit-run-N, forms-run-N (N = runs[].id) and anisotropy,
    std-vs-bound;
  - when every chart is drawn the page sets document.documentElement.dataset.reportReady = "true";
  - every number shown in a table is an element with data-source="<RFC 6901 JSON pointer into
    session.json>" and data-value="<the value, shortest round-trip>", its text the value formatted
    for reading (a std in its own element with its own data-source);
    Numbers the report computes itself carry data-derived="<JSON pointer into the report-data
    block>" instead, with data-value likewise; numbers of the tuning's record (the section
    <section id="tuning"> of a tuned unit) carry data-tune-source="<pointer into tune.json>";
  - every warning is <li class="warning" data-run="N"> (N = 0 for the session) inside run N's
    section, <section class="run" id="run-N" data-run="N">, or outside every run's section for
    N = 0; (this checker also wants each run's figures inside that run's section);
  - the outcome is <div id="outcome" data-kind="KIND">, KIND = outcome.kind, or "NOT RECORDED"
    when session.json has no outcome;
  - the page's data is one <script type="application/json" id="report-data"> block.

What this checker asserts (each problem it finds is tagged with the check's name, so the checker's
own test can tell which check caught a page broken on purpose):
  ready      reportReady becomes "true" within `ready_timeout_s`
  console    the browser logged no console error or warning (goog:loggingPrefs browser ALL)
  network    every performance entry (navigation and resource) is a file:, data: or blob: URL, and
             no element carries an http(s) src/href/srcset/poster/data attribute
  figures    every required canvas[data-figure] is present, NAME-run-N ones in run N's section,
             inside a <figure> with a non-empty
             <figcaption>, and drawn: its own pixels (getImageData) hold at least
             `kMinInkFraction` of non-transparent pixels and `kMinColours` distinct colours, and,
             when Chart.js drew it (Chart.getChart), a dataset holds at least 2 finite points (a
             chart with axes but no data is blank to an engineer, however many pixels its grid has),
             and every legend item of it lies inside the canvas (a label wider than the chart is
             cut off at its edge)
  numbers    every [data-source] element: the pointer resolves in session.json; data-value parses
             to exactly the JSON value (float equality; strings and booleans exactly; null as ""
             or "null"); the displayed text (the element's own text, without nested data-source
             elements) is a number that agrees with the value to the precision shown (half a unit
             of its last digit), or, for null, is not a number. The same for every [data-derived]
             element against the report-data block, and every [data-tune-source] against
             tune.json (there must be one, and the page must show some of it, when the unit was
             tuned; the tuning's figures are then required too)
  data       one script#report-data block, type application/json, that parses
  outcome    #outcome exists and its data-kind equals session.json's outcome.kind
  warnings   every outcome.estimate.warnings string appears in an li.warning; one starting
             "run N:" has data-run="N" and sits in run N's section; any other has data-run="0"
             and sits in no run's section. Every li.warning on the page (the report's own too)
             has a data-run that is a run number or 0, agrees with a "run N:" at the start of
             its text, and sits where its data-run says
  mentions   (optional) the page's text contains each given string (e.g. a missing file's name)
  trends     (under figures) every svg.trend (the unit's history) is laid out and draws each of its
             data-points as a circle.session with a box

Screenshots (full page and each <figure>) go to `artifacts_dir` when given.

Needs python3-selenium, chromium and chromium-driver (Debian). Chromium runs headless with every
network request refused (a proxy on a closed port, every host name unresolvable), so a page that
tries to fetch anything shows a console error and a non-file performance entry.
"""

from __future__ import annotations

import base64
import json
import math
import os
import re
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

kMinInkFraction = 0.002  # a 600×250 chart: at least 300 drawn pixels (one axis line has ~600)
kMinColours = 4          # background-only or one flat colour is not a chart
kChromiumArgs = [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>",
    "--host-resolver-rules=MAP * ~NOTFOUND", "--window-size=1280,1000",
    "--no-first-run", "--disable-extensions", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--disable-default-apps",
]


@dataclass
class Problem:
    check: str
    message: str

    def __str__(self) -> str:
        return f"[{self.check}] {self.message}"


@dataclass
class PageResult:
    problems: list[Problem] = field(default_factory=list)
    figures: list[dict] = field(default_factory=list)
    numbers_checked: int = 0
    warnings_checked: int = 0
    ready_after_s: float | None = None
    screenshots: list[Path] = field(default_factory=list)
    trends: list[dict] = field(default_factory=list)

    def add(self, check: str, message: str) -> None:
        self.problems.append(Problem(check, message))


def MissingTools() -> list[str]:
    """What the browser check needs and this machine lacks (empty when everything is there)."""
    missing = []
    try:
        import selenium  # noqa: F401  (only whether it is there)
    except ImportError:
        missing.append("python3-selenium (the Python module 'selenium' for this interpreter)")
    if not ChromiumBinary():
        missing.append("chromium")
    if not ChromedriverBinary():
        missing.append("chromium-driver (chromedriver)")
    return missing


def ChromiumBinary() -> str | None:
    override = os.environ.get("HRGBENCH_CHROMIUM")
    if override:
        return override if os.access(override, os.X_OK) else None
    return shutil.which("chromium") or shutil.which("chromium-browser")


def ChromedriverBinary() -> str | None:
    return shutil.which("chromedriver")


def ResolvePointer(document: Any, pointer: str) -> tuple[bool, Any]:
    """RFC 6901: "" is the whole document; "/a/0/b~1c" is document["a"][0]["b/c"]."""
    if pointer == "":
        return True, document
    if not pointer.startswith("/"):
        return False, None
    value = document
    for token in pointer[1:].split("/"):
        token = token.replace("~1", "/").replace("~0", "~")
        if isinstance(value, dict):
            if token not in value:
                return False, None
            value = value[token]
        elif isinstance(value, list):
            if not re.fullmatch(r"0|[1-9][0-9]*", token) or int(token) >= len(value):
                return False, None
            value = value[int(token)]
        else:
            return False, None
    return True, value


_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_NUMBER = re.compile(
    r"(?P<sign>[+-]?)(?P<int>\d*)(?:\.(?P<frac>\d*))?"
    r"(?:(?:[eE]|[×x·]10\^?)(?P<exp>[+-]?\d+))?")


def ParseDisplayedNumber(text: str) -> tuple[float, float] | None:
    """A number as a page shows it: "-1.0016e-03", "−1.00162×10⁻³", "9.961 × 10⁻⁵",
    "± 0.0095", "(3)", "0.28964". Returns (value, resolution = one unit of the last digit
    shown), or None when the text is not one number."""
    t = text.strip().translate(_SUPERSCRIPTS)
    t = t.replace("\u2212", "-").replace("\u2013", "-")
    for space in (" ", "\u00a0", "\u2009", "\u202f"):
        t = t.replace(space, "")
    if t.startswith("(") and t.endswith(")"):
        t = t[1:-1]
    if t.startswith("±"):
        t = t[1:]
    m = _NUMBER.fullmatch(t)
    if not m or not (m.group("int") or m.group("frac")):
        return None
    mantissa = float((m.group("int") or "0") + "." + (m.group("frac") or "0"))
    exponent = int(m.group("exp") or 0)
    decimals = len(m.group("frac") or "")
    sign = -1.0 if m.group("sign") == "-" else 1.0
    return sign * mantissa * 10.0**exponent, 10.0 ** (exponent - decimals)


def CheckNumber(source: str, data_value: str | None, text: str, expected: Any,
                result: PageResult, attribute: str = "data-source",
                document: str = "session.json") -> None:
    where = f"{attribute}={source!r}"
    if data_value is None:
        result.add("numbers", f"{where}: no data-value attribute")
        return
    if expected is None:
        if data_value not in ("", "null"):
            result.add("numbers", f"{where}: {document} holds null, data-value is {data_value!r}")
        if ParseDisplayedNumber(text) is not None:
            result.add("numbers", f"{where}: {document} holds null, the page shows {text!r}")
        return
    if isinstance(expected, bool):
        if data_value != ("true" if expected else "false"):
            result.add("numbers", f"{where}: {document} holds {expected}, data-value "
                                  f"{data_value!r}")
        return
    if isinstance(expected, str):
        if data_value != expected:
            result.add("numbers", f"{where}: {document} holds {expected!r}, data-value "
                                  f"{data_value!r}")
        return
    if not isinstance(expected, (int, float)):
        result.add("numbers", f"{where}: points at a {type(expected).__name__}, not a value")
        return
    try:
        attribute = float(data_value)
    except ValueError:
        result.add("numbers", f"{where}: data-value {data_value!r} is not a number")
        return
    if attribute != float(expected):
        result.add("numbers", f"{where}: data-value {data_value!r} is not {document}'s "
                              f"{expected!r}")
    shown = ParseDisplayedNumber(text)
    if shown is None:
        result.add("numbers", f"{where}: the text {text!r} is not a number (value {expected!r})")
        return
    value, resolution = shown
    # Half a unit of the last digit shown, and a little for the binary representation of both.
    tolerance = 0.5 * resolution * (1 + 1e-9) + 1e-12 * abs(float(expected))
    if not abs(value - float(expected)) <= tolerance:
        result.add("numbers", f"{where}: the text {text!r} reads {value!r}, {document} holds "
                              f"{expected!r} (allowed ±{tolerance:.3g} at the precision shown)")


TUNE_FIGURES = ["tune-rate-error-before", "tune-rate-error-after", "tune-scale-factor"]


def RequiredFigures(run_ids: Iterable[int], run_figures: Iterable[str] = (),
                    tuned: bool = False) -> list[str]:
    """The contract's figures; `run_figures` adds kinds every run must have on this page too
    (e.g. residual-histogram, residual-spectrum, conditions: issue 26's); a tuned unit's page has
    the tuning's (and tune-allan when the tuning held zero rate)."""
    names = []
    for run_id in run_ids:
        names += [f"channels-run-{run_id}", f"residuals-run-{run_id}", f"orbit-run-{run_id}",
                  f"forms-run-{run_id}"]
        names += [f"{kind}-run-{run_id}" for kind in run_figures]
    return names + ["anisotropy", "std-vs-bound"] + (TUNE_FIGURES if tuned else [])


# Runs in the page, returns what the checks need in one round trip.
_COLLECT_JS = r"""
// The run whose section holds `el`: its closest <section class="run" data-run="N">, 0 for none.
const sectionRun = (el) => {
  const section = el.closest('section.run[data-run]');
  return section ? Number(section.getAttribute('data-run')) : 0;
};
const ownText = (el) => {
  const copy = el.cloneNode(true);
  for (const inner of copy.querySelectorAll('[data-source],[data-derived],[data-tune-source]'))
    inner.remove();
  return copy.textContent.replace(/\s+/g, ' ').trim();
};
const figures = [];
for (const c of document.querySelectorAll('canvas[data-figure]')) {
  const f = { name: c.dataset.figure, width: c.width, height: c.height, inFigure: false,
              caption: '', ink: 0, colours: 0, chart: null, error: null };
  f.section = sectionRun(c);
  const fig = c.closest('figure');
  if (fig) { f.inFigure = true; const cap = fig.querySelector('figcaption');
             f.caption = cap ? cap.textContent.trim() : ''; }
  try {
    const pixels = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    let ink = 0;
    for (let i = 0; i < pixels.length; i += 4) {
      if (pixels[i + 3] === 0) continue;
      ++ink;
      if (colours.size < 4096)
        colours.add(((pixels[i] << 24) | (pixels[i + 1] << 16) | (pixels[i + 2] << 8) |
                     pixels[i + 3]) >>> 0);
    }
    f.ink = c.width * c.height > 0 ? ink / (c.width * c.height) : 0;
    f.colours = colours.size;
  } catch (e) { f.error = String(e); }
  if (window.Chart && Chart.getChart) {
    const chart = Chart.getChart(c);
    if (chart) {
      let best = 0;
      for (const ds of chart.data.datasets) {
        let n = 0;
        for (const p of ds.data) {
          const v = (p !== null && typeof p === 'object') ? (p.y !== undefined ? p.y : p.r) : p;
          if (typeof v === 'number' && Number.isFinite(v)) ++n;
        }
        best = Math.max(best, n);
      }
      // Legend items outside the canvas are cut off (Chart.js lays a too-long label out at its
      // full width and clips it at the canvas' edge): each hit box holds the item's full width.
      const boxes = (chart.legend && chart.legend.options && chart.legend.options.display !== false
                     && chart.legend.legendHitBoxes) || [];
      const cut = boxes.map((b, i) => ({ b, text: (chart.legend.legendItems[i] || {}).text }))
        .filter(({ b }) => b.left < -0.5 || b.top < -0.5 || b.left + b.width > chart.width + 0.5 ||
                           b.top + b.height > chart.height + 0.5)
        .map(({ b, text }) => String(text) + ' at ' + Math.round(b.left) + '+' +
                              Math.round(b.width) + ' of ' + chart.width + ' px');
      f.chart = { datasets: chart.data.datasets.length, mostPoints: best, legendCut: cut };
    }
  }
  figures.push(f);
}
const numbers = [...document.querySelectorAll('[data-source]')].map((el) => ({
  source: el.getAttribute('data-source'), value: el.getAttribute('data-value'), text: ownText(el),
  tag: el.tagName }));
const tuneNumbers = [...document.querySelectorAll('[data-tune-source]')].map((el) => ({
  source: el.getAttribute('data-tune-source'), value: el.getAttribute('data-value'),
  text: ownText(el), tag: el.tagName }));
const derived = [...document.querySelectorAll('[data-derived]')].map((el) => ({
  source: el.getAttribute('data-derived'), value: el.getAttribute('data-value'), text: ownText(el),
  tag: el.tagName }));
const dataBlocks = [...document.querySelectorAll('script#report-data')].map((el) => ({
  type: el.getAttribute('type'), text: el.textContent }));
const warnings = [...document.querySelectorAll('li.warning')].map((el) => ({
  text: el.textContent.replace(/\s+/g, ' ').trim(), run: el.getAttribute('data-run'),
  section: sectionRun(el) }));
const outcomes = [...document.querySelectorAll('#outcome')].map((el) => ({
  tag: el.tagName, kind: el.getAttribute('data-kind'), text: el.textContent.trim() }));
const entries = performance.getEntries()
  .filter((e) => e.entryType === 'navigation' || e.entryType === 'resource')
  .map((e) => e.name);
const linked = [];
for (const el of document.querySelectorAll('[src],[href],[srcset],[poster],object[data]')) {
  for (const attr of ['src', 'href', 'srcset', 'poster', 'data']) {
    const v = el.getAttribute(attr);
    if (v && /(^|[\s,])(https?:)?\/\//i.test(v)) linked.push(el.tagName + ' ' + attr + '=' + v);
  }
}
// The unit's trend plots (inline SVG): each point that is drawn has a box on the page.
const trends = [...document.querySelectorAll('svg.trend')].map((el) => {
  const circles = [...el.querySelectorAll('circle.session')];
  const drawn = circles.filter((c) => { const b = c.getBBox(); return b.width > 0 && b.height > 0; });
  const box = el.getBoundingClientRect();
  return { quantity: el.getAttribute('data-quantity'), points: Number(el.getAttribute('data-points')),
           drawn: drawn.length, width: box.width, height: box.height };
});
return { figures, numbers, tuneNumbers, derived, dataBlocks, warnings, outcomes, entries, linked, trends,
         text: document.body ? document.body.innerText : '' };
"""


class ReportPageChecker:
    """One headless Chromium, reused for several pages (`Check` per page). Not thread-safe."""

    def __init__(self, ready_timeout_s: float = 60.0):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        options = webdriver.ChromeOptions()
        for arg in kChromiumArgs:
            options.add_argument(arg)
        options.binary_location = ChromiumBinary()
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(ChromedriverBinary()), options=options)
        self.driver.set_page_load_timeout(ready_timeout_s)
        self.ready_timeout_s = ready_timeout_s

    def close(self) -> None:
        self.driver.quit()

    def __enter__(self) -> "ReportPageChecker":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def Check(self, html: Path, session: Any, run_ids: Iterable[int],
              artifacts_dir: Path | None = None, mentions: Iterable[str] = (),
              run_figures: Iterable[str] = (), tune: Any = None) -> PageResult:
        """`tune`: the session's tune.json when the unit was tuned (the page's tuning section
        reads it: data-tune-source pointers)."""
        result = PageResult()
        driver = self.driver
        driver.get_log("browser")  # drop what an earlier page logged
        driver.get(html.resolve().as_uri())
        start = time.monotonic()
        ready = None
        while time.monotonic() - start < self.ready_timeout_s:
            ready = driver.execute_script("return document.documentElement.dataset.reportReady")
            if ready == "true":
                result.ready_after_s = time.monotonic() - start
                break
            time.sleep(0.05)
        if ready != "true":
            result.add("ready", f"reportReady is {ready!r} after {self.ready_timeout_s:.0f} s")
        page = driver.execute_script(_COLLECT_JS)

        for entry in driver.get_log("browser"):
            if entry.get("level") in ("SEVERE", "WARNING"):
                result.add("console", f"{entry.get('level')}: {entry.get('message')}")

        for url in page["entries"]:
            if not re.match(r"(file|data|blob):", url):
                result.add("network", f"the page requested {url}")
        for link in page["linked"]:
            result.add("network", f"an element links to the network: {link}")

        self._CheckFigures(page["figures"], RequiredFigures(run_ids, run_figures, tune is not None), result)
        for t in page["trends"]:
            if t["width"] <= 0 or t["height"] <= 0 or t["drawn"] < 1 or t["drawn"] != t["points"]:
                result.add("figures", f"trend of {t['quantity']}: {t['drawn']} of "
                                      f"{t['points']} points drawn in a {t['width']:.0f}×"
                                      f"{t['height']:.0f} px plot")
        result.trends = page["trends"]
        for f in page["figures"]:
            m = re.search(r"-run-(\d+)$", f["name"])
            if m and f["section"] != int(m.group(1)):
                result.add("figures", f"{f['name']} sits in "
                           + (f"run {f['section']}'s section" if f["section"] else
                              "no run's section") + f", want <section class=\"run\" "
                           f"data-run=\"{m.group(1)}\">")

        for number in page["numbers"]:
            result.numbers_checked += 1
            found, expected = ResolvePointer(session, number["source"] or "")
            if not found:
                result.add("numbers", f"data-source={number['source']!r} (shown as "
                                      f"{number['text']!r}) is not in session.json")
                continue
            CheckNumber(number["source"], number["value"], number["text"], expected, result)

        for number in page["tuneNumbers"]:
            result.numbers_checked += 1
            if tune is None:
                result.add("numbers", f"data-tune-source={number['source']!r} on the page of a "
                                      "session without tune.json")
                continue
            found, expected = ResolvePointer(tune, number["source"] or "")
            if not found:
                result.add("numbers", f"data-tune-source={number['source']!r} (shown as "
                                      f"{number['text']!r}) is not in tune.json")
                continue
            CheckNumber(number["source"], number["value"], number["text"], expected, result,
                        attribute="data-tune-source", document="tune.json")
        if tune is not None and not page["tuneNumbers"]:
            result.add("numbers", "the session has tune.json and the page shows none of it")

        report_data = None
        if len(page["dataBlocks"]) != 1 or page["dataBlocks"][0]["type"] != "application/json":
            result.add("data", f"{len(page['dataBlocks'])} script#report-data blocks "
                               f"({[b['type'] for b in page['dataBlocks']]}), want one "
                               "application/json")
        else:
            try:
                report_data = json.loads(page["dataBlocks"][0]["text"])
            except ValueError as e:
                result.add("data", f"script#report-data is not JSON: {e}")
        for number in page["derived"]:
            result.numbers_checked += 1
            found, expected = ResolvePointer(report_data, number["source"] or "")
            if report_data is None or not found:
                result.add("numbers", f"data-derived={number['source']!r} (shown as "
                                      f"{number['text']!r}) is not in the report-data block")
                continue
            CheckNumber(number["source"], number["value"], number["text"], expected, result,
                        attribute="data-derived")

        kind = ResolvePointer(session, "/outcome/kind")[1]
        if kind is None:  # an older session: the page says so in data-kind
            kind = "NOT RECORDED"
        if len(page["outcomes"]) != 1:
            result.add("outcome", f"{len(page['outcomes'])} elements with id 'outcome', want 1")
        else:
            outcome = page["outcomes"][0]
            if outcome["tag"] != "DIV":
                result.add("outcome", f"#outcome is a <{outcome['tag'].lower()}>, want a <div>")
            if outcome["kind"] != kind:
                result.add("outcome", f"#outcome data-kind {outcome['kind']!r}, session.json "
                                      f"outcome.kind {kind!r}")

        recorded = ResolvePointer(session, "/outcome/estimate/warnings")[1] or []
        for warning in recorded:
            result.warnings_checked += 1
            self._CheckWarning(warning, page["warnings"], result)
        for shown in page["warnings"]:  # the report's own warnings too (a missing file, ...)
            self._CheckWarningPlace(shown, result)

        for text in mentions:
            if text not in page["text"]:
                result.add("mentions", f"the page does not say {text!r}")

        if artifacts_dir is not None:
            self._Screenshots(artifacts_dir, page["figures"], result)
        result.figures = page["figures"]
        return result

    @staticmethod
    def _CheckFigures(figures: list[dict], required: list[str], result: PageResult) -> None:
        by_name: dict[str, list[dict]] = {}
        for f in figures:
            by_name.setdefault(f["name"], []).append(f)
        for name in required:
            if name not in by_name:
                result.add("figures", f"no canvas[data-figure={name!r}]")
        for name, found in by_name.items():
            if len(found) > 1:
                result.add("figures", f"{len(found)} canvases named {name!r}")
            f = found[0]
            if not f["inFigure"]:
                result.add("figures", f"{name}: the canvas is not inside a <figure>")
            elif not f["caption"]:
                result.add("figures", f"{name}: its <figure> has no (or an empty) <figcaption>")
            if f["error"]:
                result.add("figures", f"{name}: its pixels cannot be read: {f['error']}")
            elif f["ink"] < kMinInkFraction or f["colours"] < kMinColours:
                result.add("figures", f"{name}: blank ({100 * f['ink']:.2f} % of "
                                      f"{f['width']}×{f['height']} pixels drawn, "
                                      f"{f['colours']} colours)")
            if f["chart"] is not None and f["chart"].get("legendCut"):
                result.add("figures", f"{name}: legend cut off at the canvas' edge: "
                                      + "; ".join(f["chart"]["legendCut"]))
            if f["chart"] is not None and f["chart"]["mostPoints"] < 2:
                result.add("figures", f"{name}: Chart.js drew it with no data "
                                      f"({f['chart']['datasets']} datasets, at most "
                                      f"{f['chart']['mostPoints']} finite points)")

    @staticmethod
    def _CheckWarning(warning: str, shown: list[dict], result: PageResult) -> None:
        norm = " ".join(str(warning).split())
        m = re.match(r"run (\d+): (.*)", norm)
        run = int(m.group(1)) if m else 0
        bodies = [norm] + ([m.group(2)] if m else [])
        matches = [w for w in shown if any(b in w["text"] for b in bodies)]
        if not matches:
            result.add("warnings", f"no li.warning says {norm!r}")
            return
        placed = [w for w in matches if w["run"] == str(run) and w["section"] == run]
        if not placed:
            where = ", ".join(f"data-run={w['run']!r} in the section of run {w['section']}"
                              if w["section"] else f"data-run={w['run']!r} outside the runs"
                              for w in matches)
            want = f"run {run}'s section" if run else "outside every run's section"
            result.add("warnings", f"{norm!r} shown as {where}; want data-run=\"{run}\" {want}")

    @staticmethod
    def _CheckWarningPlace(shown: dict, result: PageResult) -> None:
        """Any li.warning: data-run is a run number or 0, it sits in that run's section (0: in
        none), and a text starting "run N:" has data-run N."""
        text, run = shown["text"], shown["run"]
        if run is None or not re.fullmatch(r"0|[1-9][0-9]*", run):
            result.add("warnings", f"li.warning {text!r}: data-run {run!r} is not a run number")
            return
        m = re.match(r"run (\d+):", text)
        if m and m.group(1) != run:
            result.add("warnings", f"li.warning {text!r}: data-run {run!r}, its text names run "
                                   f"{m.group(1)}")
        if shown["section"] != int(run):
            where = f"run {shown['section']}'s section" if shown["section"] else "no run's section"
            result.add("warnings", f"li.warning {text!r}: data-run {run!r} but it sits in {where}")

    def _Screenshots(self, directory: Path, figures: list[dict], result: PageResult) -> None:
        from selenium.webdriver.common.by import By

        directory.mkdir(parents=True, exist_ok=True)
        driver = self.driver
        size = driver.execute_cdp_cmd("Page.getLayoutMetrics", {})["cssContentSize"]
        shot = driver.execute_cdp_cmd("Page.captureScreenshot", {
            "format": "png", "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": math.ceil(size["width"]),
                     "height": math.ceil(size["height"]), "scale": 1}})
        full = directory / "page.png"
        full.write_bytes(base64.b64decode(shot["data"]))
        result.screenshots.append(full)
        for f in figures:
            elements = driver.find_elements(By.CSS_SELECTOR, f'canvas[data-figure="{f["name"]}"]')
            if not elements:
                continue
            target = elements[0]
            parents = driver.execute_script("return arguments[0].closest('figure')", target)
            path = directory / f"figure-{re.sub(r'[^A-Za-z0-9_-]', '_', f['name'])}.png"
            (parents or target).screenshot(str(path))
            result.screenshots.append(path)
