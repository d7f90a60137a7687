#!/usr/bin/env python3
"""The session report in a real browser (issue 9 §3): headless Chromium, no network.

  report_browser_test.py --case checker   --source-dir SRC --artifacts DIR
  report_browser_test.py --case bench     --source-dir SRC --bin-dir BIN --artifacts DIR
  report_browser_test.py --case missing-run --source-dir SRC --bin-dir BIN --artifacts DIR
  report_browser_test.py --case no-outcome --source-dir SRC --bin-dir BIN --artifacts DIR

checker      the test of the test: the hand-written fixture (fixture/report.html, which keeps the
             contract) passes report_page_checker; each copy of it broken on purpose (MUTATIONS:
             a blank canvas, a wrong number, a misplaced warning, a network request, ...) fails,
             and fails in the check that should catch it.
bench        hrg-bench runs a short sequence (SEQUENCE below, 3 runs of 4 s at 100 Hz) on the
             simulated station with the example limits, three times for one serial, each session
             uploaded to a SQLite store of the test's own; hrg-report writes the third's report
             with the store (--results), so it draws the unit's trend (3 points each); the checker
             asserts the whole contract against the session.json it reads itself; the PDF, when
             hrg-report wrote one, has pages and says the outcome (pdftotext). The unit passes and
             is tuned first (hrg-bench tune, short holds): the page's tuning section against
             tune.json, and its figures.
missing-run  the same session with runs/run-002.csv deleted: the report still renders, without
             console errors, and names the missing file.
no-outcome   the same session without "outcome" (an older bench's record, or a session that never
             closed): the report renders, #outcome says NOT RECORDED, the page says "not recorded".

Screenshots (page.png and figure-NAME.png), the page, session.json and the PDF's first page go to
--artifacts/<case>/ for CI to keep. Exit codes: 0 passed; 1 failed; 77 a tool missing (skipped),
which is a failure (1) under CI=true or HRGBENCH_STRICT=1, as tests/support/required_tool.hpp.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.dont_write_bytecode = True  # nothing written into the source tree (no __pycache__ there)
sys.path.insert(0, str(Path(__file__).resolve().parent))
import report_page_checker as rpc  # noqa: E402

kSkip = 77
kChartJsCandidates = ["/usr/share/javascript/chart.js/chart.umd.min.js",
                      "/usr/share/javascript/chart.js/chart.min.js"]

# Three short runs at table rates (Ω = −1, 0.3, 1 rad/s: δ2 and every ξ determined) so that the
# example limits are all judged (at the paper's 1e-4 rad/s they are too uncertain to judge, and
# the session is an ERROR with nothing to show in the verdict).
SEQUENCE = """\
[sequence]
name = "browser-test"
description = "Three short runs for the browser test of the session report"

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
window_s = 10.0
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
free_run_s = 10.0
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

# (name, text in fixture/report.html, its replacement, the check that must catch it).
MUTATIONS = [
    ("one canvas never drawn", '{"name": "residuals-run-1"', '{"name": "residuals-run-1-undrawn"',
     "figures"),
    ("chart with axes and no data", '"points": 199', '"points": 0', "figures"),
    ("trend point not drawn", '<circle class="session" cx="80" cy="60" r="3"',
     '<circle class="session" cx="80" cy="60" r="0"', "figures"),
    ("legend label cut off", 'label: "s" + (i + 1),',
     'label: "s" + (i + 1) + " with a label far too long for its chart ".repeat(4),', "figures"),
    ("figure missing", 'data-figure="orbit-run-1"', 'data-figure="orbit-run-one"', "figures"),
    ("canvas without figcaption", "<figcaption>anisotropy</figcaption>", "", "figures"),
    ("wrong data-value", 'data-value="-0.0010016167989"', 'data-value="-0.0010016167988"',
     "numbers"),
    ("text disagrees with the value", "0.28964</td>", "0.28963</td>", "numbers"),
    ("text not a number", "2.4379e-2</td>", "about 0.024</td>", "numbers"),
    ("pointer not in session.json", 'data-source="/outcome/estimate/residual_rms"',
     'data-source="/outcome/estimate/residual_rms_total"', "numbers"),
    ("derived number wrong", '<span data-derived="/derived/decay_time_s" data-value="998.4">998<',
     '<span data-derived="/derived/decay_time_s" data-value="998.4">997<', "numbers"),
    ("figure outside its run's section", '<section class="run" id="run-2" data-run="2">',
     '<section class="run" id="run-2" data-run="7">', "figures"),
    ("report-data not JSON", '{"derived": {"decay_time_s": 998.4},', '{"derived": {decay_time_s},',
     "data"),
    ("outcome kind wrong", '<div id="outcome" data-kind="FAIL">',
     '<div id="outcome" data-kind="PASS">', "outcome"),
    ("warning missing", '<li class="warning" data-run="0">weakly', '<li data-run="0">weakly',
     "warnings"),
    ("run warning at the top", '<li class="warning" data-run="2">',
     '</ul><ul><li class="warning" data-run="2">', None),  # replaced below: moved, not copied
    ("data-run disagrees with the text", '<li class="warning" data-run="2">run 2:',
     '<li class="warning" data-run="1">run 2:', "warnings"),
    ("console error", "document.documentElement.dataset.reportReady = \"true\";",
     "console.error('x is undefined'); document.documentElement.dataset.reportReady = \"true\";",
     "console"),
    ("network request", "</body>", '<img src="http://example.com/logo.png" alt=""></body>',
     "network"),
    ("never ready", "document.documentElement.dataset.reportReady = \"true\";", "", "ready"),
]


def Strict() -> bool:
    return os.environ.get("CI") == "true" or os.environ.get("HRGBENCH_STRICT") == "1"


def RequireTools(extra: list[str]) -> None:
    missing = rpc.MissingTools() + extra
    if missing:
        print("report_browser_test: missing " + "; ".join(missing) +
              " (scripts/setup-debian.sh installs them)", file=sys.stderr)
        sys.exit(1 if Strict() else kSkip)


def ChartJs() -> str | None:
    for path in kChartJsCandidates:
        if Path(path).is_file():
            return path
    return None


def MoveRunWarningToTop(html: str) -> str:
    """The fixture with run 2's warning taken out of run 2's section and put among the session's
    warnings (data-run still "2"): the warnings check must say it is misplaced."""
    li = ('<li class="warning" data-run="2">run 2: 3 samples removed as outliers and the fit '
          'repeated without them</li>')
    assert li in html, "fixture changed: run 2's warning not found"
    html = html.replace("<ul>" + li + "</ul>", "")
    return html.replace('<ul id="session-warnings">', '<ul id="session-warnings">' + li)


def Report(result: rpc.PageResult, label: str) -> None:
    ready = "never" if result.ready_after_s is None else f"{result.ready_after_s:.2f} s"
    print(f"{label}: ready after {ready}, "
          f"{len(result.figures)} figures, {result.numbers_checked} numbers, "
          f"{result.warnings_checked} warnings checked, {len(result.screenshots)} screenshots")
    for f in result.figures:
        print(f"  figure {f['name']}: {f['width']}x{f['height']}, {100 * f['ink']:.1f} % drawn, "
              f"{f['colours']} colours, chart {f['chart']}")
    for p in result.problems:
        print(f"  PROBLEM {p}")


def CaseChecker(args: argparse.Namespace) -> int:
    chart_js = ChartJs()
    RequireTools([] if chart_js else ["libjs-chart.js (" + " or ".join(kChartJsCandidates) + ")"])
    fixture = Path(__file__).resolve().parent / "fixture"
    session = json.loads((fixture / "session.json").read_text())
    good = (fixture / "report.html").read_text().replace("/*CHART_JS*/",
                                                         Path(chart_js).read_text())
    failures = []
    out = args.artifacts / "checker"
    shutil.rmtree(out, ignore_errors=True)
    with tempfile.TemporaryDirectory(prefix="hrgbench-browser-") as tmp, \
            rpc.ReportPageChecker(ready_timeout_s=5.0) as checker:
        page = Path(tmp) / "report.html"
        page.write_text(good)
        result = checker.Check(page, session, [1, 2], artifacts_dir=out)
        Report(result, "fixture as written")
        if result.problems:
            failures.append("the fixture, which keeps the contract, was rejected")
        for name, old, new, check in MUTATIONS:
            if check is None:
                broken, check = MoveRunWarningToTop(good), "warnings"
            else:
                if good.count(old) != 1:
                    failures.append(f"mutation {name!r}: {old!r} occurs {good.count(old)} times "
                                    "in the fixture, want once")
                    continue
                broken = good.replace(old, new)
            page.write_text(broken)
            result = checker.Check(page, session, [1, 2])
            caught = [p for p in result.problems if p.check == check]
            verdict = "caught" if caught else "MISSED"
            print(f"mutation {name!r}: {verdict} by [{check}]"
                  + "".join(f"\n    {p}" for p in result.problems))
            if not caught:
                failures.append(f"mutation {name!r} was not caught by the {check} check")
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


def Run(command: list[str], log: Path, timeout_s: float = 240.0) -> int:
    start = time.monotonic()
    with open(log, "w") as out:
        code = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT,
                              timeout=timeout_s).returncode
    print(f"$ {' '.join(command)}  -> exit {code} ({time.monotonic() - start:.1f} s, log {log})")
    return code


def StationWithStore(args: argparse.Namespace, tmp: Path) -> tuple[Path, str]:
    """The simulated station, its sessions uploaded to a results store of this test's own (the
    shipped file names the repository's build/out/results.sqlite)."""
    url = f"sqlite://{tmp / 'results.sqlite'}"
    text = (args.source_dir / "bench_configs" / "station-sim.toml").read_text()
    shipped = 'url = "sqlite://../build/out/results.sqlite"'
    if shipped not in text:
        raise RuntimeError(f"station-sim.toml no longer says {shipped}: update this test")
    station = tmp / "station.toml"
    station.write_text(text.replace(shipped, f'url = "{url}"'))
    return station, url


def MakeBenchSession(args: argparse.Namespace, tmp: Path, station: Path,
                     name: str = "session") -> Path:
    """A session of the simulated station, judged against the example limits. Raises on a bench
    that did not produce one."""
    sequence = tmp / "sequence.toml"
    sequence.write_text(SEQUENCE)
    session = tmp / name
    configs = args.source_dir / "bench_configs"
    log = tmp / f"hrg-bench-{name}.log"
    code = Run([str(args.bin_dir / "hrg-bench"), "run", "--station", str(station), "--sequence",
                str(sequence), "--limits", str(configs / "limits-example.toml"), "--serial",
                "BROWSER-0001", "-o", str(session)], log)
    if code not in (0, 1):  # PASS or FAIL: the unit judged; anything else is the bench's error
        print(log.read_text())
        raise RuntimeError(f"hrg-bench exited {code}")
    return session


def ResolvePassed(session: Path) -> bool:
    """The session closed as PASS (only a passing unit is tuned)."""
    recorded = json.loads((session / "session.json").read_text())
    return (recorded.get("outcome") or {}).get("kind") == "PASS"


def WriteReport(args: argparse.Namespace, session: Path, tmp: Path,
                results_url: str = "") -> tuple[int, Path]:
    report_dir = session / "report"
    shutil.rmtree(report_dir, ignore_errors=True)  # hrg-bench may have written one: ours is new
    command = [str(args.bin_dir / "hrg-report"), str(session)]
    if results_url:
        command += ["--results", results_url]
    code = Run(command, tmp / "hrg-report.log")
    print((tmp / "hrg-report.log").read_text())
    return code, report_dir / "report.html"


def KeepArtifacts(out: Path, session: Path, html: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    shutil.copy2(session / "session.json", out / "session.json")
    if html.is_file():
        shutil.copy2(html, out / "report.html")


def CheckPdf(pdf: Path, kind: str, out: Path) -> list[str]:
    """The PDF hrg-report printed with Chromium: pages, and the outcome's word in its text."""
    problems = []
    for tool in ("pdfinfo", "pdftotext", "pdftoppm"):
        if not shutil.which(tool):
            return [f"{tool} missing (poppler-utils) to check {pdf}"]
    info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, timeout=60)
    pages = 0
    for line in info.stdout.splitlines():
        if line.startswith("Pages:"):
            pages = int(line.split()[1])
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, timeout=60).stdout
    print(f"PDF {pdf}: {pages} pages, {len(text)} characters of text")
    if pages < 1:
        problems.append(f"{pdf}: no pages (pdfinfo: {info.stdout.strip()} {info.stderr.strip()})")
    if kind and kind not in text:
        problems.append(f"{pdf}: its text does not say the outcome {kind!r}")
    subprocess.run(["pdftoppm", "-png", "-r", "60", "-f", "1", "-l", "1", str(pdf),
                    str(out / "pdf-page")], timeout=60)
    return problems


def CaseSession(args: argparse.Namespace, case: str) -> int:
    RequireTools([] if (args.bin_dir / "hrg-report").is_file() else
                 [f"{args.bin_dir / 'hrg-report'} (build the target hrg-report)"])
    out = args.artifacts / case
    shutil.rmtree(out, ignore_errors=True)
    failures = []
    with tempfile.TemporaryDirectory(prefix="hrgbench-browser-") as tmp_name:
        tmp = Path(tmp_name)
        station, results_url = StationWithStore(args, tmp)
        # bench: the unit's history from the store, so the report draws its trend: two earlier
        # sessions of the same serial, then the one reported.
        earlier = 2 if case == "bench" else 0
        for k in range(earlier):
            MakeBenchSession(args, tmp, station, f"earlier-{k + 1}")
        session_dir = MakeBenchSession(args, tmp, station)
        # bench: the unit tuned when it passed (hrg-bench tune writes tune.json and makes the
        # report again with its tuning section).
        tune_path = session_dir / "tune.json"
        if case == "bench" and not ResolvePassed(session_dir):
            failures.append("the bench session did not pass: no tuning to report")
        elif case == "bench":
            code = Run([str(args.bin_dir / "hrg-bench"), "tune", str(session_dir),
                        "--verify-turns", "2", "--refine-turns", "2", "--zero-rate-hold", "10"],
                       tmp / "hrg-bench-tune.log")
            if code not in (0, 1) or not tune_path.is_file():
                print((tmp / "hrg-bench-tune.log").read_text())
                failures.append(f"hrg-bench tune exited {code} and wrote no {tune_path}")
        # hrg-bench writes the report itself when the session closes and prints its path.
        bench_html = session_dir / "report" / "report.html"
        if case == "bench":
            if not bench_html.is_file():
                failures.append(f"hrg-bench wrote no {bench_html}")
            elif str(bench_html) not in (tmp / "hrg-bench-session.log").read_text():
                failures.append(f"hrg-bench did not print the report's path {bench_html}")
        mentions = []
        if case == "missing-run":
            (session_dir / "runs" / "run-002.csv").unlink()
            mentions = ["run-002.csv"]
        elif case == "no-outcome":  # a session of an older bench, or one that never closed
            recorded = json.loads((session_dir / "session.json").read_text())
            del recorded["outcome"]
            (session_dir / "session.json").write_text(json.dumps(recorded, indent=2))
            mentions = ["not recorded"]
        code, html = WriteReport(args, session_dir, tmp, results_url if earlier else "")
        session = json.loads((session_dir / "session.json").read_text())
        KeepArtifacts(out, session_dir, html)
        if not html.is_file():
            print(f"FAIL: hrg-report exited {code} and wrote no {html}")
            return 1
        if code != 0 and case == "bench":
            failures.append(f"hrg-report exited {code}")
        urls = sorted(set(re.findall(r"https?://[^\s\"'<>)]*", html.read_text(errors="replace"))))
        if urls:  # hrg-report's own promise: nothing in the file that could be fetched
            failures.append(f"{html} holds http(s) URLs: {urls[:5]}")
        run_ids = [r.get("id") for r in session.get("runs", []) if r.get("status") == "complete"
                   and (session_dir / r.get("file", "")).is_file()]
        with rpc.ReportPageChecker(ready_timeout_s=60.0) as checker:
            # Issue 26's figures: what each run's fit left and its conditions over the run (the
            # bench's runs record temperature and frequency at their start and end).
            tune = json.loads(tune_path.read_text()) if tune_path.is_file() else None
            result = checker.Check(html, session, run_ids, artifacts_dir=out, mentions=mentions,
                                   run_figures=["residual-histogram", "residual-spectrum",
                                                "conditions"], tune=tune)
        Report(result, case)
        failures += [str(p) for p in result.problems]
        if earlier:
            # One point per session of the unit that determined the quantity (this one included),
            # each drawn (the checker checks drawn == points); a trend per key quantity.
            sessions = earlier + 1
            print(f"trends: {[(t['quantity'], t['points'], t['drawn']) for t in result.trends]}")
            if not any(t["points"] == sessions for t in result.trends):
                failures.append(f"the store holds {sessions} sessions of the unit and no trend "
                                f"draws all of them: {result.trends}")
            for t in result.trends:
                if t["points"] > sessions:
                    failures.append(f"trend of {t['quantity']}: {t['points']} points, the store "
                                    f"holds {sessions} sessions of the unit")
        pdf = html.parent / "report.pdf"
        if pdf.is_file():
            kind = session.get("outcome", {}).get("kind", "")
            failures += CheckPdf(pdf, kind, out)
            shutil.copy2(pdf, out / "report.pdf")
        else:
            print(f"note: no {pdf} (hrg-report prints it only when Chromium works for it)")
    print(f"artifacts: {out}")
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", required=True,
                        choices=["checker", "bench", "missing-run", "no-outcome"])
    parser.add_argument("--source-dir", type=Path, required=True)
    parser.add_argument("--bin-dir", type=Path)
    parser.add_argument("--artifacts", type=Path, required=True)
    args = parser.parse_args()
    if args.case == "checker":
        return CaseChecker(args)
    if args.bin_dir is None:
        parser.error("--bin-dir is needed for the session cases")
    return CaseSession(args, args.case)


if __name__ == "__main__":
    sys.exit(main())
