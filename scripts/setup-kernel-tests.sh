#!/usr/bin/env bash
# Prepares the kernel tests (ctest -L kernel): installs QEMU and a static busybox, and caches Debian's
# own kernel with its CAN modules in BUILD_DIR/kernel-cache, because the machine's kernel may have
# neither AF_CAN nor vcan. See tests/integration/kernel/README.md.
#
# Usage: scripts/setup-kernel-tests.sh [BUILD_DIR]      (default: build)
#
# Idempotent: packages are installed only when missing, and the kernel is fetched only when the cache
# does not hold the package that linux-image-amd64 currently depends on. Nothing is downloaded from
# anywhere but Debian's archive, and the kernel package is never installed (only unpacked into the
# cache), so the host's boot setup is untouched.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(realpath -m "${1:-$root/build}")"
cache="$build/kernel-cache"

# The modules the guest loads. Their dependencies are added from each module's own `depends=` field
# below, so a kernel that moves code between modules still gets a complete set.
wanted_modules=(can can-raw can-bcm can-dev vcan vxcan)

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive

# --- Host tools ----------------------------------------------------------------------------------
# qemu-system-x86 brings SeaBIOS and the option ROMs that -kernel boots need; busybox-static is
# copied into every initramfs and also provides cpio for building it. binutils (objcopy) and xz are
# used on the host to shrink binaries and decompress .ko.xz; both come with build-essential.
packages=(qemu-system-x86 busybox-static xz-utils binutils)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
apt_updated=0
if ((${#missing[@]})); then
  echo "setup-kernel-tests: installing ${missing[*]}"
  $sudo apt-get -o DPkg::Lock::Timeout=600 update -qq
  apt_updated=1
  $sudo apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends "${missing[@]}"
fi

# --- Which kernel ---------------------------------------------------------------------------------
# linux-image-amd64 is Debian's meta package; the real image is its (only) linux-image-* dependency.
resolve_kernel_package() {
  apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*\)$/\1/p' | head -n1
}
kernel_pkg="$(resolve_kernel_package)"
if [ -z "$kernel_pkg" ] && [ "$apt_updated" -eq 0 ]; then
  # A fresh container has no package lists yet.
  $sudo apt-get -o DPkg::Lock::Timeout=600 update -qq
  kernel_pkg="$(resolve_kernel_package)"
fi
if [ -z "$kernel_pkg" ]; then
  echo "setup-kernel-tests: cannot resolve the package behind linux-image-amd64 (apt-cache depends)" >&2
  exit 1
fi
kernel_version="$(apt-cache show --no-all-versions "$kernel_pkg" | sed -n 's/^Version: //p' | head -n1)"
stamp="$kernel_pkg $kernel_version"

if [ -f "$cache/COMPLETE" ] && [ "$(cat "$cache/COMPLETE")" = "$stamp" ]; then
  echo "setup-kernel-tests: kernel cache up to date ($stamp) in $cache"
  exit 0
fi

# --- Fetch and unpack -----------------------------------------------------------------------------
# Everything is built in a scratch folder next to the cache and moved into place at the end, so an
# interrupted run never leaves a cache that looks complete.
echo "setup-kernel-tests: fetching $stamp into $cache"
mkdir -p "$build"
work="$(mktemp -d "$build/kernel-cache.tmp.XXXXXX")"
trap 'rm -rf "$work"' EXIT
# apt drops privileges to _apt for downloads; that user must be able to write the folder.
chmod 0777 "$work"
(cd "$work" && apt-get download "$kernel_pkg=$kernel_version")
deb="$(ls "$work"/*.deb)"

# Only the image and the CAN modules are extracted (about 10 MB of the package's 400 MB unpacked).
mkdir -p "$work/root"
# The module patterns start with '*' so they match /lib/modules and a merged /usr/lib/modules alike.
dpkg-deb --fsys-tarfile "$deb" |
  tar -x -C "$work/root" --wildcards \
    './boot/vmlinuz-*' '*/kernel/net/can/*' '*/kernel/drivers/net/can/*'
rm -f "$deb"

vmlinuz="$(find "$work/root/boot" -maxdepth 1 -name 'vmlinuz-*' | head -n1)"
if [ -z "$vmlinuz" ]; then
  echo "setup-kernel-tests: $kernel_pkg has no boot/vmlinuz-*" >&2
  exit 1
fi

# Flatten the modules into one folder, decompressed: busybox insmod in the guest may not read .ko.xz
# or .ko.zst, and decompressing once here is cheaper than in an emulated CPU at every boot.
mkdir -p "$work/new/modules"
cp "$vmlinuz" "$work/new/vmlinuz"
while IFS= read -r -d '' ko; do
  base="$(basename "$ko")"
  case "$ko" in
    *.ko.xz) xz -dc "$ko" >"$work/new/modules/${base%.xz}" ;;
    *.ko.zst) zstd -qdc "$ko" >"$work/new/modules/${base%.zst}" ;;
    *.ko.gz) gzip -dc "$ko" >"$work/new/modules/${base%.gz}" ;;
    *.ko) cp "$ko" "$work/new/modules/$base" ;;
  esac
done < <(find "$work/root" -name '*.ko*' -print0)

# The `depends=` field of a module's .modinfo section, as modinfo -F depends would print it (read
# directly: busybox modinfo only looks modules up by name in the running kernel's modules.dep).
module_depends() {
  tr '\0' '\n' <"$work/new/modules/$1.ko" | sed -n 's/^depends=//p' | head -n1 | tr ',' ' '
}

# Depth-first over the dependencies gives a load order where every module follows what it needs
# (can-dev before vcan, can before can-raw). Module names use '-' or '_' interchangeably.
declare -A visited=()
order=()
visit() {
  local name="$1" file
  file="$name"
  [ -f "$work/new/modules/$file.ko" ] || file="${name//_/-}"
  [ -f "$work/new/modules/$file.ko" ] || file="${name//-/_}"
  if [ ! -f "$work/new/modules/$file.ko" ]; then
    echo "setup-kernel-tests: module $name is not among the extracted CAN modules" >&2
    exit 1
  fi
  [ -z "${visited[$file]:-}" ] || return 0
  visited[$file]=1
  local dep
  for dep in $(module_depends "$file"); do visit "$dep"; done
  order+=("$file.ko")
}
for m in "${wanted_modules[@]}"; do visit "$m"; done

# Keep only what the guest loads: the initramfs is copied into guest memory at every boot.
for ko in "$work/new/modules"/*.ko; do
  [ -n "${visited[$(basename "$ko" .ko)]:-}" ] || rm -f "$ko"
done
printf '%s\n' "${order[@]}" >"$work/new/load-order"
basename "$vmlinuz" | sed 's/^vmlinuz-//' >"$work/new/kernel-release"
echo "$stamp" >"$work/new/COMPLETE"

rm -rf "$cache"
mv "$work/new" "$cache"
echo "setup-kernel-tests: cached $(cat "$cache/kernel-release") in $cache," \
  "modules in load order: ${order[*]}"
