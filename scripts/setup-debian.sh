#!/usr/bin/env bash
# Installs what hrgbench needs from Debian 12's own packages. Idempotent: only missing packages are
# installed, so a second run costs one dpkg query. Nothing is downloaded from anywhere but Debian.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev            # estimator
  libspdlog-dev libfmt-dev # logs in the tools
  libcli11-dev             # command lines
  nlohmann-json3-dev       # session.json, --json output
  libtomlplusplus-dev      # config files
  libgtest-dev libgmock-dev googletest
  libbenchmark-dev
  libmodbus-dev            # rate table driver
  socat                    # RTU tests: a pty pair between driver and simulated table
  can-utils                # log2asc/canplayer read the CAN log in the tests
  stress-ng                # the load check: the suite with both cores busy beside it
  libjs-chart.js           # hrg-report: Chart.js inlined into the session report's page
  gnuplot-nox              # hrg-report: the figures as SVG for documents
  chromium                 # hrg-report: the page printed to PDF (headless); the browser test
  chromium-driver          # the browser test drives Chromium (tests/integration/report_browser)
  python3-selenium         # the browser test's WebDriver client (Debian's /usr/bin/python3)
  python3-canmatrix        # the gyro CAN DBC read by a tool not ours (tests/unit/gyro_can)
  poppler-utils            # the browser test checks the report's PDF (pdfinfo, pdftotext)
  libsqlite3-dev sqlite3   # results database (src/results): SQLite engine; sqlite3 in its tests
  libpq-dev                # results database: PostgreSQL engine (libpq)
  postgresql-15            # results tests and benchmark: a throwaway server (initdb, pg_ctl)
  libcpp-httplib-dev       # hrg-bench serve: the operator panel's web server (cpp-httplib)
  clang-format             # the formatting check (scripts/check-format.sh, ctest format.*)
  python3                  # the layer check (tests/architecture) and the Python-driven tests
  systemd-container        # the package test boots a systemd guest (systemd-nspawn)
  lintian                  # the package test: Debian's checks of the station's .deb
  curl                     # the package test: the panel's page and API inside the guest
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get -o DPkg::Lock::Timeout=600 update -qq
  $sudo apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi
