#!/usr/bin/env bash
# Runs a test program inside Debian's own kernel under QEMU, with the CAN modules loaded and a CAN FD
# capable vcan0 up, because the host kernel may have neither AF_CAN nor vcan. The guest's console
# (the test's own output included) is copied to stdout, so it lands in the ctest log.
#
# Usage: scripts/run-in-kernel.sh BUILD_DIR [--with PATH]... -- COMMAND [ARG...]
#   BUILD_DIR   build tree holding kernel-cache/ (made by scripts/setup-kernel-tests.sh)
#   --with PATH also put PATH (a program, a data file or a folder) into the guest at the same path;
#               programs bring the libraries ldd lists. Use it for helper processes and scripts.
#   COMMAND     the program to run in the guest (with its libraries, at its host path). A script
#               must start with #!/bin/sh: the guest has busybox, not bash.
# Exit code: the command's exit code inside the guest; 1 when the guest gives no result (hung,
# crashed, setup failed); 77 (ctest's skip) when qemu or the kernel cache is missing on a developer
# machine. In a strict run (CI=true, or HRGBENCH_STRICT=1 as scripts/run-tests.sh sets) a missing
# prerequisite is a failure instead: the README's test command must never skip these tests.
#
# Environment: HRGBENCH_KERNEL_TIMEOUT_S (default 300) bounds the whole VM run;
# HRGBENCH_KERNEL_MEMORY_MB (default 256) is the guest's memory; HRGBENCH_KERNEL_KEEP=1 keeps the
# staging folder and initramfs for debugging. GTEST_* and HRGBENCH_* variables are passed on to the
# command in the guest, which also gets HRGBENCH_CAN_IFACE=vcan0 and HRGBENCH_REQUIRE_VCAN=1.
set -euo pipefail

readonly kResultTag="HRGBENCH-KERNEL-RESULT"
me="run-in-kernel"

usage() {
  echo "usage: $0 BUILD_DIR [--with PATH]... -- COMMAND [ARG...]" >&2
  exit 2
}

[ $# -ge 1 ] || usage
build="$(realpath -m "$1")"
shift
with=()
while [ $# -gt 0 ]; do
  case "$1" in
    --with)
      [ $# -ge 2 ] || usage
      with+=("$(realpath -s -m "$2")")
      shift 2
      ;;
    --) shift; break ;;
    *) usage ;;
  esac
done
[ $# -ge 1 ] || usage
# -s: keep symlinks, so a multi-call program keeps the argv[0] it was given.
command_path="$(realpath -s -m "$1")"
shift
command_args=("$@")

cache="$build/kernel-cache"
timeout_s="${HRGBENCH_KERNEL_TIMEOUT_S:-300}"
memory_mb="${HRGBENCH_KERNEL_MEMORY_MB:-256}"

# --- Prerequisites --------------------------------------------------------------------------------
# A developer machine without QEMU skips (77); CI fails, so a broken setup is never reported green.
unavailable() {
  local fix="run: bash scripts/setup-kernel-tests.sh $build"
  if [ "${CI:-}" = "true" ] || [ "${HRGBENCH_STRICT:-}" = "1" ]; then
    echo "$me: FAIL: $1 (a strict run: CI=true or HRGBENCH_STRICT=1; an error, not a skip; $fix)" >&2
    exit 1
  fi
  echo "$me: SKIP: $1 ($fix)" >&2
  exit 77
}
command -v qemu-system-x86_64 >/dev/null || unavailable "qemu-system-x86_64 not found"
busybox_bin="/bin/busybox"
[ -x "$busybox_bin" ] || unavailable "$busybox_bin not found (package busybox-static)"
# The guest has no libc of its own to offer busybox: it must be the static build.
if ldd "$busybox_bin" >/dev/null 2>&1; then
  unavailable "$busybox_bin is dynamically linked (install busybox-static, not busybox)"
fi
[ -f "$cache/COMPLETE" ] || unavailable "no kernel cache in $cache"
if [ ! -x "$command_path" ]; then
  echo "$me: $command_path is not an executable (not built?)" >&2
  exit 1
fi

# --- Staging: the guest's root file system --------------------------------------------------------
mkdir -p "$build/kernel-run" "$build/kernel-logs"
stage="$(mktemp -d "$build/kernel-run/stage.XXXXXX")"
# shellcheck disable=SC2317  # called by the EXIT trap
cleanup() {
  if [ "${HRGBENCH_KERNEL_KEEP:-0}" = "1" ]; then
    echo "$me: kept $stage" >&2
  else
    rm -rf "$stage"
  fi
}
trap cleanup EXIT
root="$stage/root"
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,proc,sys,dev,tmp,run,modules}
cp "$busybox_bin" "$root/bin/busybox"
cp "$cache/modules/"*.ko "$cache/load-order" "$root/modules/"

is_elf() { [ "$(head -c 4 "$1" | od -An -c | tr -d ' ')" = "177ELF" ]; }

# Copies one file to the same path in the guest. ELF files lose their debug info (the initramfs is
# copied into guest memory at every boot; a RelWithDebInfo test binary is mostly DWARF) and bring
# every library ldd lists, also at its host path, so the loader finds them where it looks on the host.
declare -A copied=()
copy_file() {
  local src="$1"
  [ -z "${copied[$src]:-}" ] || return 0
  copied[$src]=1
  mkdir -p "$root$(dirname "$src")"
  if is_elf "$src"; then
    objcopy --strip-debug "$src" "$root$src" 2>/dev/null || cp -L "$src" "$root$src"
    chmod --reference="$src" "$root$src"
    local lib
    # ldd prints "name => /path (addr)" and "/path (addr)"; linux-vdso has no file.
    while IFS= read -r lib; do
      copy_file "$lib"
    done < <(ldd "$src" 2>/dev/null | sed -n -e 's/^.*=> \(\/[^ ]*\) (.*$/\1/p' \
      -e 's/^[[:space:]]*\(\/[^ ]*\) (.*$/\1/p')
  else
    cp -L "$src" "$root$src"
  fi
}
copy_path() {
  local src="$1" f
  if [ -d "$src" ]; then
    while IFS= read -r -d '' f; do copy_file "$f"; done < <(find -L "$src" -type f -print0)
  elif [ -e "$src" ]; then
    copy_file "$src"
  else
    echo "$me: --with $src does not exist" >&2
    exit 1
  fi
}
copy_path "$command_path"
for w in "${with[@]}"; do copy_path "$w"; done

# Shell-quotes one word for the guest's busybox sh.
quote() { printf "'%s'" "${1//\'/\'\\\'\'}"; }

# The command line and environment, written as a sourced file so no argument is re-split.
{
  echo "# Written by scripts/run-in-kernel.sh"
  for name in $(compgen -e); do
    case "$name" in
      HRGBENCH_KERNEL_*) ;;  # the harness's own settings
      GTEST_* | HRGBENCH_*) echo "export $name=$(quote "${!name}")" ;;
    esac
  done
  echo "export GTEST_COLOR=no HRGBENCH_IN_VM=1 HRGBENCH_REQUIRE_VCAN=1 HRGBENCH_CAN_IFACE=vcan0"
  echo "workdir=$(quote "$PWD")"
  printf 'set --'
  printf ' %s' "$(quote "$command_path")"
  for a in "${command_args[@]}"; do printf ' %s' "$(quote "$a")"; done
  echo
} >"$root/test-command"

# PID 1 of the guest. Every way out prints the result line and powers off; if /init itself dies the
# kernel panics, panic=-1 reboots and -no-reboot ends QEMU, which the host reads as "no result".
cat >"$root/init" <<'EOF'
#!/bin/busybox sh
/bin/busybox --install -s
export PATH=/bin:/sbin:/usr/bin:/usr/sbin
mount -t devtmpfs devtmpfs /dev
# The kernel may not have found a console before /dev existed; take ttyS0 explicitly.
exec 0<>/dev/console 1>&0 2>&0
mount -t proc proc /proc
mount -t sysfs sysfs /sys
# No tmpfs on /tmp or /run: the root is already a writable RAM file system, and a mount there would
# hide test programs that live under /tmp on the host.

finish() {
  echo "HRGBENCH-KERNEL-RESULT rc=$1 stage=$2"
  sync
  poweroff -f
}

# Modules in dependency order (written by setup-kernel-tests.sh): can-dev before vcan, can before
# can-raw. Any failure is a setup error, reported as such rather than as a test failure.
while read -r module; do
  insmod "/modules/$module" || finish 125 "insmod-$module"
done </modules/load-order
ip link add dev vcan0 type vcan || finish 125 "vcan0-add"
# MTU 72 (CANFD_MTU) makes vcan0 accept CAN FD frames; the default 16 is classic only.
ip link set vcan0 mtu 72 up || finish 125 "vcan0-up"
ip link set lo up

. /test-command
mkdir -p "$workdir" && cd "$workdir"
printf '\n--- %s: running %s\n' "$(uname -r)" "$*"
"$@"
finish "$?" test
EOF
chmod 0755 "$root/init"

# newc is the only cpio format the kernel unpacks; busybox's cpio writes it, so the host needs no
# separate cpio package. Uncompressed: copying it is cheaper than inflating it on an emulated CPU.
initramfs="$stage/initramfs.cpio"
(cd "$root" && find . | "$busybox_bin" cpio -o -H newc >"$initramfs" 2>/dev/null)

# --- Boot ------------------------------------------------------------------------------------------
log="$build/kernel-logs/$(basename "$command_path").console.log"
kernel_release="$(cat "$cache/kernel-release")"
echo "$me: booting $kernel_release (QEMU TCG, ${memory_mb} MB) for $command_path" \
  "(initramfs $(($(stat -c %s "$initramfs") / 1024 / 1024)) MiB, limit ${timeout_s} s)"
start_ns="$(date +%s%N)"
# /dev/kvm on the CI machines cannot run a stock kernel, so plain TCG emulation; it boots in seconds.
# stdin is /dev/null so QEMU never puts the caller's terminal into raw mode. The sed drops carriage
# returns and SeaBIOS's terminal escapes, which would otherwise garble the ctest log.
# no_timer_check: on a loaded host the emulated CPU can miss the kernel's boot-time check that the
# IO-APIC timer ticks ("IO-APIC + timer doesn't work!", a panic before /init); the check tests the
# host's load, not the test.
set +e
timeout --kill-after=10 "$timeout_s" qemu-system-x86_64 \
  -accel tcg -m "$memory_mb" -smp 1 \
  -nodefaults -no-user-config -nographic -serial stdio -no-reboot -net none \
  -kernel "$cache/vmlinuz" -initrd "$initramfs" \
  -append "console=ttyS0 quiet loglevel=3 panic=-1 rdinit=/init no_timer_check" </dev/null |
  sed -u -e 's/\r//g' -e 's/\x1b\[[0-9;?]*[A-Za-z]//g' -e 's/\x1bc//g' | tee "$log"
statuses=("${PIPESTATUS[@]}")
set -e
elapsed_ms="$((($(date +%s%N) - start_ns) / 1000000))"
elapsed_s="$((elapsed_ms / 1000)).$(printf '%03d' $((elapsed_ms % 1000)))"

result="$(grep -a -o -E "^$kResultTag rc=[0-9]+ stage=[^ ]+" "$log" | tail -n1 || true)"
if [ -z "$result" ]; then
  if [ "${statuses[0]}" -eq 124 ] || [ "${statuses[0]}" -eq 137 ]; then
    echo "$me: FAIL: guest gave no result within ${timeout_s} s (hung?); console in $log" >&2
  else
    echo "$me: FAIL: guest ended without a result line (qemu exit ${statuses[0]}; kernel panic or" \
      "/init crash?) after ${elapsed_s} s; console in $log" >&2
  fi
  exit 1
fi
rc="$(sed -n 's/.* rc=\([0-9]*\).*/\1/p' <<<"$result")"
stage_name="${result##*stage=}"
if [ "$stage_name" != "test" ]; then
  echo "$me: FAIL: guest setup failed at $stage_name (rc $rc) after ${elapsed_s} s" >&2
  exit 1
fi
echo "$me: $(basename "$command_path") exited $rc in the guest; boot, run and power-off took" \
  "${elapsed_s} s"
# 77 would read as "skipped" to ctest, but inside the VM nothing may skip for lack of a kernel.
if [ "$rc" -eq 77 ]; then
  echo "$me: the command returned 77 inside the guest; reported as a failure" >&2
  exit 1
fi
exit "$rc"
