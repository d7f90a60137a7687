#!/usr/bin/env python3
"""The line view in a real browser (issue 26 §3): headless Chromium against `hrg-results serve` on
a line's PostgreSQL (a throwaway server of Debian's postgresql-15 on a Unix socket, as the C++
tests' postgres_server.hpp), nothing from a network.

  line_view_browser_test.py --source-dir SRC --bin-dir BIN --artifacts DIR

Five sessions of three stations are imported (hand-made session folders with known outcomes, two
of them a unit's first pass and retest); the page shows each station's last session and the day's
yield, and every number on it is the one psql reads from the store. Exit codes: 0 passed; 1 failed;
77 a tool missing (skipped), which is a failure (1) under CI=true or HRGBENCH_STRICT=1.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.dont_write_bytecode = True
kSkip = 77
kPgBin = Path("/usr/lib/postgresql/15/bin")
kChromiumArgs = [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--proxy-server=127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
    "--window-size=1280,1000", "--no-first-run", "--disable-extensions",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]
kWaitS = 60.0  # a hang guard only

# (station, serial, started, outcome): SN-1 fails then passes its retest on st-a; st-b's last
# session is an ERROR (says nothing about the unit); st-c ran yesterday only.
SESSIONS = [
    ("st-a", "SN-1", "2026-11-26T08:00:00Z", "FAIL"),
    ("st-a", "SN-1", "2026-11-26T09:00:00Z", "PASS"),
    ("st-b", "SN-2", "2026-11-26T08:30:00Z", "PASS"),
    ("st-b", "SN-3", "2026-11-26T10:00:00Z", "ERROR"),
    ("st-c", "SN-4", "2026-11-25T16:00:00Z", "PASS"),
]


def Skip(why: str) -> int:
    print(f"SKIP: {why}")
    strict = os.environ.get("CI") == "true" or os.environ.get("HRGBENCH_STRICT") == "1"
    return 1 if strict else kSkip


def SessionDocument(i: int, station: str, serial: str, started: str, outcome: str) -> dict:
    return {
        "format": "hrgbench-session", "version": 1, "state": "closed",
        "unit": {"serial": serial}, "station": {"name": station},
        "software": {"version": "fixture"},
        "config_sha256": {"station": "aa", "sequence": "bb", "limits": "cc"},
        "started": {"utc": started, "monotonic_ns": i}, "ended": {"utc": started, "monotonic_ns": i + 1},
        "sample_rate_hz": 100.0,
        "runs": [{"id": 1, "file": "runs/run-001.csv", "omega_rad_s": 0.1, "status": "complete"}],
        "outcome": {"kind": outcome, "reason": f"{outcome.lower()} <b>&</b> {serial}",
                    "exit_code": {"PASS": 0, "FAIL": 1, "ERROR": 2}[outcome]},
    }


class Postgres:
    def __init__(self, work: Path):
        self.dir = work / "pg"
        self.dir.mkdir()
        self.as_root = os.geteuid() == 0
        if self.as_root:
            shutil.chown(self.dir, "postgres")

    def run(self, *command: str) -> None:
        full = ["runuser", "-u", "postgres", "--", *command] if self.as_root else list(command)
        subprocess.run(full, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       timeout=180)

    def start(self) -> None:
        data = str(self.dir / "data")
        self.run(str(kPgBin / "initdb"), "-D", data, "-A", "trust", "-U", "postgres", "-E", "UTF8",
                 "--locale=C", "--no-sync")
        self.run(str(kPgBin / "pg_ctl"), "-D", data, "-l", str(self.dir / "server.log"), "-w",
                 "-t", "120", "-o", f"-k {self.dir} -c listen_addresses='' -p 5432 -c fsync=off",
                 "start")
        self.psql("postgres", "CREATE DATABASE line")

    def stop(self) -> None:
        self.run(str(kPgBin / "pg_ctl"), "-D", str(self.dir / "data"), "-m", "immediate", "-w",
                 "stop")

    def psql(self, db: str, sql: str) -> str:
        return subprocess.run(["psql", "-X", "-A", "-t", "-q", "-v", "ON_ERROR_STOP=1", "-h",
                               str(self.dir), "-p", "5432", "-U", "postgres", "-d", db, "-c", sql],
                              check=True, capture_output=True, text=True, timeout=60).stdout

    def url(self, db: str) -> str:
        return f"postgresql:///{db}?host={self.dir}&port=5432&user=postgres"


def Check(condition: bool, what: str) -> None:
    if not condition:
        raise AssertionError(what)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--bin-dir", required=True)
    parser.add_argument("--artifacts", required=True)
    args = parser.parse_args()
    for tool in ("chromium", "chromedriver", "psql"):
        if shutil.which(tool) is None and not (tool == "chromium" and shutil.which("chromium-browser")):
            return Skip(f"{tool} not installed")
    if not (kPgBin / "initdb").exists():
        return Skip("postgresql-15 not installed")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        from selenium.webdriver.common.by import By
    except ImportError:
        return Skip("python3-selenium not installed")

    work = Path(tempfile.mkdtemp(prefix="hrgbench-lineview-"))
    os.chmod(work, 0o755)
    pg = Postgres(work)
    server = None
    driver = None
    try:
        pg.start()
        results = Path(args.bin_dir) / "hrg-results"
        db = ["--db", pg.url("line")]
        dirs = []
        for i, (station, serial, started, outcome) in enumerate(SESSIONS):
            folder = work / "sessions" / f"s{i}"
            folder.mkdir(parents=True)
            (folder / "session.json").write_text(
                json.dumps(SessionDocument(i, station, serial, started, outcome), indent=2,
                           sort_keys=True) + "\n")
            dirs.append(str(folder))
        subprocess.run([str(results), *db, "import", *dirs], check=True, timeout=120)
        server = subprocess.Popen([str(results), *db, "serve", "--port", "0", "--today",
                                   "2026-11-26"], stdout=subprocess.PIPE, text=True)
        line = server.stdout.readline()  # "line view: http://127.0.0.1:PORT/"
        Check(line.startswith("line view: http://127.0.0.1:"), f"serve printed {line!r}")
        url = line.split(": ", 1)[1].strip()

        options = webdriver.ChromeOptions()
        for arg in kChromiumArgs:
            options.add_argument(arg)
        options.binary_location = shutil.which("chromium") or shutil.which("chromium-browser")
        driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
        driver.set_page_load_timeout(kWaitS)
        driver.get(url)
        artifacts = Path(args.artifacts)
        artifacts.mkdir(parents=True, exist_ok=True)
        driver.save_screenshot(str(artifacts / "line-view.png"))

        # Every station's last session, as psql reads it.
        rows = driver.find_elements(By.CSS_SELECTOR, "#stations tr[data-station]")
        shown = {r.get_attribute("data-station"): [c.text for c in r.find_elements(By.TAG_NAME, "td")]
                 for r in rows}
        stored = pg.psql("line", "SELECT s.station, s.serial, s.outcome FROM session s WHERE "
                         "s.started_utc = (SELECT max(e.started_utc) FROM session e WHERE "
                         "e.station = s.station) ORDER BY s.station").split()
        Check(sorted(shown) == ["st-a", "st-b", "st-c"], f"stations shown: {sorted(shown)}")
        for entry in stored:
            station, serial, outcome = entry.split("|")
            Check(shown[station][1] == serial and shown[station][6] == outcome,
                  f"{station}: page {shown[station]}, store {entry}")
        Check(shown["st-a"][5] == "retest 2", f"st-a's last is a retest: {shown['st-a']}")
        Check(shown["st-a"][3] == "2026-11-26T09:00:00.000000Z", f"time text: {shown['st-a']}")
        # Text from the store is text on the page, never markup.
        Check(shown["st-b"][7] == "error <b>&</b> SN-3", f"reason: {shown['st-b'][7]!r}")

        # Today's yield: PASS over PASS + FAIL of the day's sessions (st-c ran yesterday).
        judged = int(pg.psql("line", "SELECT count(*) FROM session WHERE started_utc >= "
                             "'2026-11-26' AND started_utc < '2026-11-27' AND outcome IN "
                             "('PASS', 'FAIL')"))
        passed = int(pg.psql("line", "SELECT count(*) FROM session WHERE started_utc >= "
                             "'2026-11-26' AND started_utc < '2026-11-27' AND outcome = 'PASS'"))
        Check((judged, passed) == (3, 2), f"psql: {passed} of {judged}")
        text = driver.find_element(By.ID, "line-yield").text
        Check(text.startswith(f"{100.0 * passed / judged:.1f} % ({passed} PASS of {judged} judged;"
                              f" first pass 50.0 %; 4 sessions)"), f"line yield: {text!r}")
        yields = {r.get_attribute("data-station"): r.find_element(By.CLASS_NAME, "yield").text
                  for r in driver.find_elements(By.CSS_SELECTOR, "#yield tr[data-station]")}
        Check(yields == {"st-a": "50.0 %", "st-b": "100.0 %"}, f"per station: {yields}")
        # Read-only: nothing but GET is answered with the page.
        Check(int(pg.psql("line", "SELECT count(*) FROM session")) == len(SESSIONS), "rows changed")
        print("line view: passed")
        return 0
    except (AssertionError, subprocess.SubprocessError) as error:
        print(f"FAILED: {error}")
        return 1
    finally:
        if driver is not None:
            driver.quit()
        if server is not None:
            server.terminate()
            server.wait(timeout=30)
        try:
            pg.stop()
        except subprocess.SubprocessError:
            pass
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
