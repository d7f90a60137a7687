#!/bin/bash
# The station package's life inside the guest that station_service_test.sh boots: systemd is PID 1
# here (systemd-nspawn over a throwaway overlay of the host's root), so this is what a line's
# machine does: dpkg installs, the postinst creates the user and starts the unit, systemctl stops
# and restarts it, dpkg purges. Run as the guest's only job (a oneshot unit); every check is a line
# "ok: ..." or "FAIL: ..." in /out/checks.txt, and /out/done says the script reached its end.
# Arguments: none; the package is /pkg/hrgbench.deb.
set -uo pipefail
out=/out
checks=$out/checks.txt
: >"$checks"
ok() { echo "ok: $*" >>"$checks"; }
fail() { echo "FAIL: $*" >>"$checks"; }
check() {  # check "what" command...: ok when the command succeeds
  local what=$1
  shift
  if "$@" >>"$out/commands.log" 2>&1; then ok "$what"; else fail "$what (exit $?)"; fi
}
require() {  # as check, and the rest is pointless without it: stop here
  check "$@"
  if tail -1 "$checks" | grep -q '^FAIL'; then
    echo "the rest depends on the failed check" >>"$checks"
    exit 1
  fi
}
# Generous hang guards, in steps: the guest's clock is the host's, nothing asserts a duration.
wait_for() {  # wait_for seconds command...
  local tries=$(($1 * 5))
  shift
  for ((i = 0; i < tries; ++i)); do
    "$@" >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  return 1
}
base=http://127.0.0.1:8080
get() { curl --silent --show-error --max-time 20 "$@"; }
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }

# What the machine holds before: every path of the system's trees (where a package can write;
# not /home, /root or the folders of whoever else is at work on the host, which the overlay shows
# live), less the volatile ones and those the guest's systemd itself writes as it runs.
manifest() {
  find /etc /usr /var /opt /srv /boot /bin /sbin /lib /lib64 -xdev \( -path /var/tmp \
    -o -path /var/log -o -path /var/cache -o -path /var/lib/systemd/catalog \
    -o -path /var/lib/systemd/random-seed -o -path /var/lib/systemd/linger \
    -o -path /var/lib/systemd/timers -o -path /var/backups \) -prune -o -printf '%p %u:%g %m\n' 2>/dev/null |
    LC_ALL=C sort
}
# Whatever happens, the unit's status and journal for the artifacts.
diagnose() {
  systemctl status hrgbench.service --no-pager >"$out/status.txt" 2>&1
  journalctl -u hrgbench.service --no-pager >"$out/journal.txt" 2>&1
}
trap diagnose EXIT
# A container image's policy-rc.d (Docker's "exit 101") forbids maintainer scripts to start
# services; a station's machine has none. Gone before the first list, so it is no difference.
rm -f /usr/sbin/policy-rc.d
manifest >"$out/before.txt"
cat /etc/passwd /etc/group >"$out/accounts-before.txt"

# 1. Install: the postinst creates the user, enables and starts the unit.
require "dpkg -i installs the package" dpkg -i /pkg/hrgbench.deb
check "the user hrgbench exists, a system user without a login shell" \
  sh -c 'getent passwd hrgbench | grep -q ":/var/lib/hrgbench:/usr/sbin/nologin$" &&
         [ "$(id -u hrgbench)" -lt 1000 ]'
check "the unit is enabled" sh -c '[ "$(systemctl is-enabled hrgbench.service)" = enabled ]'
check "the unit is active after the install" wait_for 60 systemctl is-active --quiet hrgbench.service
diagnose
require "the panel answers on 127.0.0.1:8080" wait_for 60 get -f -o /dev/null "$base/api/state"
systemd-analyze verify hrgbench.service >"$out/verify.txt" 2>&1
verify_status=$?
if [ "$verify_status" -eq 0 ] && [ ! -s "$out/verify.txt" ]; then
  ok "systemd-analyze verify of the installed unit: clean"
else
  fail "systemd-analyze verify (exit $verify_status): $(tr '\n' ' ' <"$out/verify.txt")"
fi
systemd-analyze security hrgbench.service --no-pager >"$out/security.txt" 2>&1 || true

# 2. The service as systemd runs it: its user, its state folder, its hardening in force.
pid=$(systemctl show -p MainPID --value hrgbench.service)
uid=$(awk '/^Uid:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
check "the panel runs as hrgbench (pid $pid)" [ "$uid" = "$(id -u hrgbench)" ]
check "the panel runs with no_new_privs" grep -q '^NoNewPrivs:[[:space:]]*1' "/proc/$pid/status"
check "the panel has no capabilities" grep -q '^CapEff:[[:space:]]*0000000000000000' "/proc/$pid/status"
# The options of the mount each path lies on, as the panel's mount namespace sees them.
for path in /usr /etc /var/lib/hrgbench /home /tmp; do
  echo "$path $(nsenter -t "$pid" -m findmnt --noheadings --output OPTIONS --target "$path")"
done >"$out/panel-mounts.txt"
check "the panel's /usr, /etc and /home are read-only, its state folder writable" sh -c "
  grep -qE '^/usr ro(,|\$)' '$out/panel-mounts.txt' && grep -qE '^/etc ro(,|\$)' '$out/panel-mounts.txt' &&
  grep -qE '^/home ro(,|\$)' '$out/panel-mounts.txt' &&
  grep -qE '^/var/lib/hrgbench rw(,|\$)' '$out/panel-mounts.txt'"
check "the panel has its own /tmp (PrivateTmp)" sh -c "
  [ \"\$(nsenter -t $pid -m stat -c %d:%i /tmp)\" != \"\$(stat -c %d:%i /tmp)\" ]"
check "the state folder belongs to hrgbench" \
  sh -c '[ "$(stat -c %U:%G:%a /var/lib/hrgbench)" = hrgbench:hrgbench:750 ]'

# 3. The page and the API over loopback.
get -D "$out/page.headers" -o "$out/page.html" "$base/"
check "GET / is the panel's page" sh -c "grep -q '^HTTP/1.1 200' '$out/page.headers' &&
  grep -qi '<html' '$out/page.html' && grep -q 'panel.js' '$out/page.html'"
get -D "$out/state.headers" -o "$out/state.json" "$base/api/state"
check "GET /api/state is 200" grep -q '^HTTP/1.1 200' "$out/state.headers"
check "/api/state: the installed station and its sequences and limits" python3 -c "
import json; d = json.load(open('$out/state.json'))
assert d['station'] == 'sim-station', d['station']
assert d['sequences'] and d['limits'], d"

# 4. One session from the panel, end to end, as the service: the sessions folder and the SQLite
# store in /var/lib/hrgbench, the report (figures, PDF by Chromium) under the hardening.
sequence=$(python3 -c "import json; d=json.load(open('$out/state.json')); print(d['sequences'][0]['id'])")
limits=$(python3 -c "import json; d=json.load(open('$out/state.json')); print(d['limits'][0]['id'])")
get -o "$out/start.json" -H 'Content-Type: application/json' -H "Origin: $base" \
  --data "{\"operator\": \"OP-PKG\", \"serial\": \"SIM-0001\", \"sequence\": $sequence, \"limits\": $limits}" "$base/api/start"
session=$(json 'd.get("session", "")' <"$out/start.json" 2>/dev/null)
require "POST /api/start starts a session ($(cat "$out/start.json"))" [ -n "$session" ]
# The production sequence's operator steps (mount, remove): answered as the panel's dialog does.
prompt_open() {  # prompt_open ID: the session waits for the operator at prompt ID
  get "$base/api/state" | python3 -c "
import json, sys; s = json.load(sys.stdin)['session']
sys.exit(0 if s and s.get('prompt') == '$1' else 1)"
}
answer_prompt() {  # answer_prompt ID
  wait_for 300 prompt_open "$1" &&
    get -f -o /dev/null -H 'Content-Type: application/json' -H "Origin: $base" \
      --data "{\"id\": \"$1\", \"answer\": \"confirm\", \"operator\": \"OP-PKG\"}" \
      "$base/api/prompt"
}
check "the operator's first prompt (mount) is confirmed from the panel" answer_prompt mount
check "the operator's last prompt (remove) is confirmed from the panel" answer_prompt remove
session_over() {
  get "$base/api/state" | python3 -c "
import json, sys; s = json.load(sys.stdin)['session']
sys.exit(0 if s and not s['running'] else 1)"
}
require "the session ends (hang guard 600 s)" wait_for 600 session_over
get "$base/api/state" >"$out/state-after.json"
check "the session PASSed: exit code 0" python3 -c "
import json; s = json.load(open('$out/state-after.json'))['session']
assert s['exit'] == {'exit_code': 0}, s"
dir=/var/lib/hrgbench/sessions/$session
# The panel's sessions leave their report to a job of their own (hrg-bench --report background):
# report/job.json says "written" once it is there.
report_written() {
  python3 -c "
import json, sys; j = json.load(open('$dir/report/job.json'))
sys.exit(0 if j['state'] == 'written' else 1)"
}
check "the report job wrote the report (report/job.json; hang guard 600 s)" wait_for 600 report_written
check "the session's record and report are in the state folder, owned by hrgbench" sh -c "
  [ \"\$(stat -c %U '$dir/session.json')\" = hrgbench ] && [ -s '$dir/report/report.html' ]"
check "the report's PDF was printed by Chromium inside the service" [ -s "$dir/report/report.pdf" ]
check "the session is in the SQLite store in the state folder" sh -c "
  [ \"\$(sqlite3 /var/lib/hrgbench/results.sqlite 'select count(*) from session')\" = 1 ]"
check "the record says who confirmed each prompt" python3 -c "
import json; p = json.load(open('$dir/session.json')).get('prompts') or []
assert [(x['id'], x['answer'], x['by'], x['how']) for x in p] == [
    ('mount', 'confirmed', 'OP-PKG', 'panel'), ('remove', 'confirmed', 'OP-PKG', 'panel')], p"
check "the store names the operator who started it" sh -c "
  [ \"\$(sqlite3 /var/lib/hrgbench/results.sqlite 'select operator from session')\" = OP-PKG ]"
check "GET the session's report over the panel" \
  get -f -o /dev/null "$base/sessions/$session/report/report.html"
check "the panel's log is in the journal" \
  sh -c "journalctl -u hrgbench.service --no-pager | grep -q 'panel: session $session'"

# 5. Stop: the panel exits on SIGTERM, cleanly; start again.
check "systemctl stop" systemctl stop hrgbench.service
check "the unit is inactive, its result success, the panel's exit code 0" sh -c '
  [ "$(systemctl is-active hrgbench.service)" = inactive ] &&
  [ "$(systemctl show -p Result --value hrgbench.service)" = success ] &&
  [ "$(systemctl show -p ExecMainStatus --value hrgbench.service)" = 0 ]'
check "no process of hrgbench is left after the stop" sh -c '! pgrep -u hrgbench'
check "systemctl start" systemctl start hrgbench.service
check "the panel answers again" wait_for 60 get -f -o /dev/null "$base/api/state"

# 5b. Stop during a session: systemd signals the panel only (KillMode=mixed), the panel aborts its
# session once (table to zero, gyro safe), the record says ABORTED, the panel exits 0. With the
# child signalled too (KillMode=control-group) that would be its second interrupt: exit at once.
get -o "$out/start2.json" -H 'Content-Type: application/json' -H "Origin: $base" \
  --data "{\"operator\": \"OP-PKG\", \"serial\": \"SIM-0002\", \"sequence\": $sequence, \"limits\": $limits}" "$base/api/start"
session2=$(json 'd.get("session", "")' <"$out/start2.json" 2>/dev/null)
require "a second session starts ($(cat "$out/start2.json"))" [ -n "$session2" ]
dir2=/var/lib/hrgbench/sessions/$session2
check "its record is open" wait_for 120 test -s "$dir2/session.json"
check "systemctl stop during the session" systemctl stop hrgbench.service
check "the unit stopped cleanly: result success, the panel's exit code 0" sh -c '
  [ "$(systemctl show -p Result --value hrgbench.service)" = success ] &&
  [ "$(systemctl show -p ExecMainStatus --value hrgbench.service)" = 0 ]'
# The record names the panel's abort (SIGINT: "aborted by operator"); had systemd signalled the
# child too, it would say "stopped by SIGTERM" (so it did with KillMode=control-group).
check "the stopped session's record is closed as ABORTED by the panel's abort" python3 -c "
import json; o = json.load(open('$dir2/session.json')).get('outcome') or {}
assert o.get('kind') == 'ABORTED' and 'aborted by operator' in o.get('reason', ''), o"
check "no process of hrgbench is left after the stop during a session" sh -c '! pgrep -u hrgbench'
check "systemctl start after it" systemctl start hrgbench.service
check "the panel answers after it" wait_for 60 get -f -o /dev/null "$base/api/state"

# 6. An update (the same package again: dpkg's upgrade path): the station's edit of a conffile is
# kept, the sessions and the store are kept, the panel is restarted.
echo "# a station's own edit" >>/etc/hrgbench/station.toml
old_pid=$(systemctl show -p MainPID --value hrgbench.service)
check "dpkg -i again (the update path)" dpkg -i --force-confold /pkg/hrgbench.deb
check "the edited conffile is kept" grep -q "^# a station's own edit" /etc/hrgbench/station.toml
check "the panel was restarted by the update" sh -c "
  [ \"\$(systemctl show -p MainPID --value hrgbench.service)\" != '$old_pid' ] &&
  systemctl is-active --quiet hrgbench.service"
check "the sessions and the store survive the update" sh -c "
  [ -s '$dir/session.json' ] && [ -s /var/lib/hrgbench/results.sqlite ]"
check "the panel answers after the update" wait_for 60 get -f -o /dev/null "$base/api/state"

# 7. Purge while it runs: the prerm stops it; nothing of it is left but the user (Debian keeps
# system users) and dpkg's own bookkeeping.
check "dpkg --purge" dpkg --purge hrgbench
check "no process of hrgbench is left after the purge" sh -c '! pgrep -u hrgbench'
check "the unit is gone" sh -c '! systemctl cat hrgbench.service'
check "/etc/hrgbench and /var/lib/hrgbench are gone" sh -c '[ ! -e /etc/hrgbench ] && [ ! -e /var/lib/hrgbench ]'
manifest >"$out/after.txt"
cat /etc/passwd /etc/group >"$out/accounts-after.txt"
# dpkg's own files change with any install; the account files change by the user's line.
diff "$out/before.txt" "$out/after.txt" |
  grep -E '^[<>]' |
  grep -vE '^[<>] /var/lib/dpkg/(status|status-old|available|diversions|statoverride|triggers/[^ ]*|lock[^ ]*|info/format) ' |
  grep -vE '^[<>] /etc/(passwd|group|shadow|gshadow)-? ' >"$out/left.txt"
if [ -s "$out/left.txt" ]; then
  fail "the purge left or changed: $(head -20 "$out/left.txt" | tr '\n' ';')"
else
  ok "the purge left no path behind (dpkg's database and the account files aside)"
fi
diff "$out/accounts-before.txt" "$out/accounts-after.txt" | grep -E '^[<>]' >"$out/accounts-left.txt"
check "the accounts differ by the hrgbench user and group only" python3 -c "
lines = open('$out/accounts-left.txt').read().split('\n')
lines = [l for l in lines if l]
assert len(lines) == 2 and all(l.startswith('> hrgbench:') for l in lines), lines"

echo finished >"$out/done"
