#!/bin/bash
# The station as a Debian package, built, installed, run as a systemd service and purged
# (issue 26 §5; docs/station-install.md says what this proves and what it does not).
#
# 1. `cpack -G DEB` packs this build's binaries by the project's install rules (packaging/); the
#    package's files, conffiles and control fields are checked, and lintian must find no error or
#    warning.
# 2. The package's life on a machine whose PID 1 is systemd. This machine's PID 1 is not systemd
#    (CI's machines are VMs with their own init), so the test boots one: systemd-nspawn runs the
#    host's own systemd as PID 1 of a container whose root is an overlay of the host's root on a
#    tmpfs (in a private mount namespace), with a private network (its own loopback only) and the
#    source and build folders made inaccessible (an installed program must not need them). Inside,
#    in_guest.sh installs with dpkg, checks the service as systemd runs it, drives the panel over
#    loopback through one session, stops, updates and purges, and lists what was left. Every write
#    lands in the tmpfs, which goes with the namespace: the host's dpkg database, /etc and
#    /var are never touched, on CI or on a developer's machine.
#
# Needs root (nspawn, mount), systemd-container, lintian, curl (scripts/setup-debian.sh). A missing
# tool or no root: exit 77 (skipped) on a developer's machine, 1 (failed) under CI=true or
# HRGBENCH_STRICT=1. Arguments: BUILD_DIR SOURCE_DIR ARTIFACTS_DIR.
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
artifacts=$3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

missing() {
  echo "package test: $1" >&2
  if [ "${CI:-}" = true ] || [ "${HRGBENCH_STRICT:-}" = 1 ]; then exit 1; fi
  exit 77
}
[ "$(id -u)" -eq 0 ] || missing "needs root (systemd-nspawn, mount)"
for tool in cpack dpkg-deb lintian systemd-nspawn unshare curl sqlite3; do
  command -v "$tool" >/dev/null || missing "$tool missing (bash scripts/setup-debian.sh installs it)"
done

rm -rf "$artifacts"
mkdir -p "$artifacts/package" "$artifacts/out"
artifacts=$(cd "$artifacts" && pwd)
fail() {
  echo "package test: FAIL: $*" >&2
  exit 1
}

# 1. The package.
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$artifacts/package" >"$artifacts/cpack.log" 2>&1 ||
  fail "cpack failed: $(tail -20 "$artifacts/cpack.log")"
debs=("$artifacts"/package/hrgbench_*.deb)
[ "${#debs[@]}" -eq 1 ] && [ -f "${debs[0]}" ] || fail "cpack made no single hrgbench_*.deb: ${debs[*]}"
deb=${debs[0]}
echo "package test: built $(basename "$deb") ($(du -k "$deb" | cut -f1) kB)"
dpkg-deb --contents "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$artifacts/contents.txt"
for path in /usr/bin/hrg-bench /usr/bin/hrg-results /usr/bin/hrg-report /usr/bin/hrg-estimate \
  /etc/hrgbench/station.toml /etc/hrgbench/sequence-production.toml \
  /etc/hrgbench/sequence-production-adaptive.toml \
  /etc/hrgbench/limits-example.toml /lib/systemd/system/hrgbench.service \
  /usr/lib/sysusers.d/hrgbench.conf /usr/share/doc/hrgbench/copyright \
  /usr/share/doc/hrgbench/changelog.gz /usr/share/doc/hrgbench/station-install.md; do
  grep -qx "$path" "$artifacts/contents.txt" || fail "the package lacks $path"
done
if grep -E '^/var/|^/(home|root|tmp)/' "$artifacts/contents.txt"; then
  fail "the package ships files where systemd or the machine owns the place (above)"
fi
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles >"$artifacts/conffiles.txt"
diff <(sort "$artifacts/conffiles.txt") <(printf '%s\n' /etc/hrgbench/limits-example.toml \
  /etc/hrgbench/sequence-production-adaptive.toml /etc/hrgbench/sequence-production.toml \
  /etc/hrgbench/station.toml) ||
  fail "the conffiles are not the station's four files (above)"
dpkg-deb --field "$deb" Depends >"$artifacts/depends.txt"
grep -q 'libjs-chart.js' "$artifacts/depends.txt" || fail "Depends lacks libjs-chart.js"
grep -q 'libc6' "$artifacts/depends.txt" || fail "Depends has no shared-library dependencies"
lintian --fail-on error,warning --tag-display-limit 0 "$deb" >"$artifacts/lintian.txt" 2>&1 ||
  fail "lintian: $(cat "$artifacts/lintian.txt")"
echo "package test: lintian: no error or warning"

# 2. The guest: an overlay of / on a tmpfs, systemd as its PID 1, in_guest.sh its only job (and
# no timers: a daily job of the host's, dpkg's backup say, would write beside the test).
scratch=$(mktemp -d /tmp/hrgbench-package-test.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
cat >"$artifacts/hrgbench-package-test.service" <<'EOF'
[Unit]
Description=hrgbench package test (tests/integration/package/in_guest.sh)
Wants=basic.target
After=basic.target
[Service]
Type=oneshot
ExecStart=/bin/bash /pkgtest/in_guest.sh
StandardOutput=file:/out/in_guest.log
StandardError=inherit
TimeoutStartSec=1200
ExecStopPost=/bin/systemctl poweroff --no-block
EOF
# On a machine whose PID 1 is systemd, nspawn gets its own scope from it (the usual way); without
# one (CI's VMs) it stays in the caller's cgroup.
scope_options=(--keep-unit)
if [ -d /run/systemd/system ]; then scope_options=(); fi
guest_status=0
unshare --mount --propagation private bash -euo pipefail -c '
  scratch=$1 deb=$2 here=$3 out=$4 source_dir=$5 build=$6
  shift 6
  mount -t tmpfs -o mode=0755 hrgbench-package-test "$scratch"
  mkdir "$scratch/lower" "$scratch/upper" "$scratch/work" "$scratch/root"
  mount --bind / "$scratch/lower"
  mount -t overlay overlay \
    -o "lowerdir=$scratch/lower,upperdir=$scratch/upper,workdir=$scratch/work" "$scratch/root"
  cp "$out/../hrgbench-package-test.service" "$scratch/root/etc/systemd/system/"
  # The source and build folders hidden under empty read-only tmpfs (nspawn'"'"'s --inaccessible
  # needs a host systemd); the build first, as it may lie inside the source.
  for dir in "$build" "$source_dir"; do
    if [ -d "$scratch/root$dir" ]; then
      mount -t tmpfs -o ro,mode=0000,size=4k hrgbench-hidden "$scratch/root$dir"
    fi
  done
  timeout --kill-after=30 1500 systemd-nspawn --quiet --directory="$scratch/root" \
    --register=no "$@" --link-journal=no --console=pipe --private-network \
    --bind="$out:/out" --bind-ro="$deb:/pkg/hrgbench.deb" --bind-ro="$here:/pkgtest" \
    --boot systemd.unit=hrgbench-package-test.service systemd.mask=timers.target </dev/null
' unshare-guest "$scratch" "$deb" "$here" "$artifacts/out" "$source_dir" "$build" \
  "${scope_options[@]}" \
  >"$artifacts/nspawn.log" 2>&1 || guest_status=$?

cat "$artifacts/out/checks.txt" 2>/dev/null || true
[ -f "$artifacts/out/done" ] ||
  fail "the guest did not finish in_guest.sh (nspawn exit $guest_status; $artifacts/nspawn.log, $artifacts/out/)"
if grep -q '^FAIL' "$artifacts/out/checks.txt"; then fail "checks failed in the guest (above)"; fi
if [ -e /etc/hrgbench ]; then fail "the host has /etc/hrgbench: the guest's overlay leaked"; fi
passed=$(grep -c '^ok' "$artifacts/out/checks.txt")
echo "package test: $passed checks passed in the guest"
