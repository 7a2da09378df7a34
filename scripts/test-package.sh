#!/usr/bin/env bash
# Checks the Debian package scripts/package.sh built (or the .deb given): its files, and that
# every shared library the binary and its OpenImageIO plugin need comes from a package it
# depends on. Then, with --install, installs it with `apt-get install ./omnishadow_*.deb`,
# renders the demo scene with /usr/bin/omnishadow (no arguments but the size: the scene comes
# from /usr/share/omnishadow), and purges the package again. --install needs root and changes
# the machine's packages, so it is no part of scripts/test.sh or CI: run it in a throwaway
# container or before a release.
#
# --chroot [DIR] does the same in a clean root instead of this machine, which already has every
# dependency (a Depends that is missing, or a library loaded only at run time, goes unnoticed
# here): a minimal Debian 12 made with `debootstrap --variant=minbase bookworm`, kept in DIR
# (default build-package/chroot/) with its package lists and every .deb downloaded, so that a
# second run skips debootstrap and the downloads and needs no network (checked with unshare -n).
# Each run copies that pristine root, runs `apt-get install -y ./omnishadow_*.deb` in the copy
# with chroot (/proc, /dev and /dev/pts mounted, unmounted on exit), renders the demo from
# /usr/bin, reads an image through the OpenImageIO plugin (`omnishadow diff` of two PPM
# files) and checks that `omnishadow devices` lists the software device. Needs root and, the
# first time, the network (deb.debian.org: debootstrap, then about 185 MB of the package's
# dependencies, 283 packages), so it is no part of CI either. Installs debootstrap if it is
# missing. Takes about 3 minutes the first time, 1.5-2 later (copying the root and unpacking).
# Usage: scripts/test-package.sh [--install | --chroot [DIR]] [package.deb]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
mode=check
if [[ "${1:-}" == "--install" ]]; then mode=install; shift; fi
chroot_dir="$root/build-package/chroot"
if [[ "${1:-}" == "--chroot" ]]; then
  mode=chroot
  shift
  if [[ -n "${1:-}" && "$1" != *.deb ]]; then chroot_dir=$1; shift; fi
fi
deb=${1:-$(ls "$root"/build-package/omnishadow_*_amd64.deb)}
deb=$(realpath "$deb")
fail() { echo "test-package: $*" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dpkg-deb -c "$deb" | awk '{print $6}' >"$work/files"
for file in ./usr/bin/omnishadow ./usr/lib/omnishadow/libomnishadow_oiio.so \
            ./usr/share/man/man1/omnishadow.1.gz ./usr/share/doc/omnishadow/README.md \
            ./usr/share/omnishadow/demo/room.gltf ./usr/share/omnishadow/demo/room.lights.json; do
  grep -qx "$file" "$work/files" || fail "$deb has no $file"
done
depends=$(dpkg-deb -f "$deb" Depends)
# The package names alone, one a line.
dpkg-deb -f "$deb" Depends | tr ',|' '\n\n' | awk '{print $1}' >"$work/depends"
# Every library the binary and the plugin need, found on this machine, belongs to a package in
# Depends (the plugin is dlopen'ed, so only its own NEEDED entries say what it loads).
dpkg-deb -x "$deb" "$work/root"
for elf in "$work/root/usr/bin/omnishadow" "$work/root/usr/lib/omnishadow/libomnishadow_oiio.so"; do
  for needed in $(objdump -p "$elf" | awk '/NEEDED/ {print $2}'); do
    path=$(ldd "$elf" | awk -v lib="$needed" '$1 == lib {print $3}')
    [[ -n "$path" ]] || fail "$needed: not found on this machine"
    package=$(dpkg -S "$(realpath "$path")" 2>/dev/null | head -1 | cut -d: -f1) ||
      package=$(dpkg -S "$path" | head -1 | cut -d: -f1)
    grep -qxF "$package" "$work/depends" ||
      fail "$(basename "$elf") needs $needed ($package), which is not in Depends: $depends"
  done
done
zcat "$work/root/usr/share/man/man1/omnishadow.1.gz" | grep -q -- '--job-timeout' ||
  fail "the man page lacks batch's options"
echo "test-package: $(basename "$deb"): files and Depends ($depends) ok"
[[ "$mode" != check ]] || exit 0
((EUID == 0)) || fail "--$mode needs root"

if [[ "$mode" == install ]]; then
  if [[ "$(dpkg-query -W -f='${Status}' omnishadow 2>/dev/null)" == "install ok installed" ]]; then
    fail "omnishadow is installed already; not touching it"
  fi
  # Purged, not removed: a removed package stays known to dpkg ("rc").
  trap 'apt-get purge -y -qq omnishadow >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$deb" >/dev/null
  mkdir "$work/render"
  (cd "$work/render" && /usr/bin/omnishadow render --width 160 --height 120 -o demo.png)
  [[ "$(head -c 8 "$work/render/demo.png" | od -An -tx1 | tr -d ' \n')" == 89504e470d0a1a0a ]] ||
    fail "/usr/bin/omnishadow render wrote no PNG"
  /usr/bin/omnishadow devices >/dev/null
  echo "test-package: apt-get installed it, /usr/bin/omnishadow rendered the demo; purging it"
  exit 0
fi

# --chroot: a pristine minimal Debian 12, made once, and a throwaway copy of it per run.
pristine="$chroot_dir/bookworm-minbase"
run="$chroot_dir/run"
archives="$chroot_dir/apt-archives"  # downloaded .debs, kept for the next run
mkdir -p "$chroot_dir" "$archives/partial"
unmount_all() {
  local point
  for point in "$run/var/cache/apt/archives" "$run/dev/pts" "$run/dev" "$run/proc"; do
    if mountpoint -q "$point" 2>/dev/null; then umount "$point" || umount -l "$point"; fi
  done
}
# Never delete through a mount (the copy has the host's /dev bound into it while it runs).
remove_run() {
  unmount_all
  if [[ -e "$run" ]]; then rm -rf --one-file-system "$run"; fi
}
trap 'remove_run; rm -rf "$work"' EXIT
trap 'exit 1' INT TERM HUP  # through the EXIT trap: nothing stays mounted
if [[ ! -e "$pristine/.omnishadow-pristine" ]]; then
  command -v debootstrap >/dev/null ||
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
  rm -rf --one-file-system "$pristine"
  echo "test-package: debootstrap --variant=minbase bookworm $pristine (once)"
  debootstrap --variant=minbase bookworm "$pristine" http://deb.debian.org/debian \
    >"$chroot_dir/debootstrap.log" 2>&1 || { tail -20 "$chroot_dir/debootstrap.log" >&2; exit 1; }
  # The package lists too, so that a later run with every .deb in $archives needs no network.
  chroot "$pristine" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin apt-get update -qq \
    >>"$chroot_dir/debootstrap.log" 2>&1 || { tail -20 "$chroot_dir/debootstrap.log" >&2; exit 1; }
  touch "$pristine/.omnishadow-pristine"
fi
remove_run
cp -a "$pristine" "$run"
cp -L /etc/resolv.conf "$run/etc/resolv.conf"
mount -t proc proc "$run/proc"
mount --bind /dev "$run/dev"
mount --bind /dev/pts "$run/dev/pts"  # apt's and dpkg's terminal logs want one
mount --bind "$archives" "$run/var/cache/apt/archives"
cp "$deb" "$run/tmp/"
: >"$chroot_dir/apt.log"
# A clean environment: nothing of this machine's (LD_PRELOAD, OMNISHADOW_*, EGL_*) leaks in.
in_root() {
  chroot "$run" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
    DEBIAN_FRONTEND=noninteractive "$@"
}
install_deb() {
  in_root sh -c "cd /tmp && apt-get install -y ./$(basename "$deb")" >>"$chroot_dir/apt.log" 2>&1
}
# Lists older than the mirror name .debs it no longer has: then update them and try again.
install_deb || { in_root apt-get update -qq >>"$chroot_dir/apt.log" 2>&1 && install_deb; } ||
  { tail -30 "$chroot_dir/apt.log" >&2; fail "apt-get install ./$(basename "$deb") failed"; }
# shellcheck disable=SC2016 # ${binary:Package} is dpkg-query's, not the shell's
echo "test-package: apt-get installed it into a clean bookworm root" \
  "($(in_root dpkg-query -W -f='${binary:Package}\n' | wc -l) packages there now)"
in_root sh -c 'mkdir -p /tmp/render && cd /tmp/render &&
  /usr/bin/omnishadow render --width 160 --height 120 -o demo.png' ||
  fail "/usr/bin/omnishadow render failed in the clean root"
[[ "$(head -c 8 "$run/tmp/render/demo.png" | od -An -tx1 | tr -d ' \n')" == 89504e470d0a1a0a ]] ||
  fail "/usr/bin/omnishadow render wrote no PNG in the clean root"
# A 2x2 binary PPM: neither PNG nor EXR, so only the OpenImageIO plugin reads it.
in_root sh -c "cd /tmp/render &&
  printf 'P6\n2 2\n255\n\377\0\0\0\377\0\0\0\377\377\377\377' >a.ppm &&
  cp a.ppm b.ppm && /usr/bin/omnishadow diff a.ppm b.ppm" ||
  fail "/usr/bin/omnishadow diff could not read PPM files (the OpenImageIO plugin)"
in_root /usr/bin/omnishadow devices >"$work/devices" || fail "omnishadow devices failed"
grep -qi software "$work/devices" ||
  fail "omnishadow devices lists no software device: $(cat "$work/devices")"
echo "test-package: in the clean root /usr/bin/omnishadow rendered the demo" \
  "($(file -b "$run/tmp/render/demo.png" | cut -d, -f2 | tr -d ' ')), read PPM through the plugin" \
  "and listed these devices:"
sed 's/^/  /' "$work/devices"
