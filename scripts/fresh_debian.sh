#!/usr/bin/env bash
# scripts/fresh_debian.sh [demo|test] [ROOT_DIR]: runs one of the README's two commands
# (scripts/demo.sh or scripts/test.sh) on a fresh Debian 12 root, as a newcomer would on a new
# machine: debootstrap --variant=minbase bookworm into ROOT_DIR (default /var/tmp/tessera-fresh),
# git and ca-certificates added (a minbase root has no git to clone with), a clean clone of this
# repository's HEAD, then the command in a chroot, timed. The root is kept for inspection and
# removed by the next run; /proc, /dev and /sys are unmounted on every exit.
#
# Needs root, debootstrap and Debian's mirror. Outside CI (CI runs scripts/test.sh itself on a
# clean checkout).
set -euo pipefail
WHAT="${1:-demo}"
R="${2:-/var/tmp/tessera-fresh}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
case "$WHAT" in demo|test) ;; *) echo "usage: $0 [demo|test] [ROOT_DIR]" >&2; exit 2 ;; esac
[ "$(id -u)" -eq 0 ] || { echo "fresh_debian: needs root (debootstrap, chroot, mount)" >&2; exit 2; }
command -v debootstrap >/dev/null || { echo "fresh_debian: install debootstrap first" >&2; exit 2; }

unmount() { for m in proc dev sys; do umount -R "$R/$m" 2>/dev/null || true; done; }
trap unmount EXIT
unmount
rm -rf "$R"
echo "fresh_debian: debootstrap bookworm into $R ($(date -u +%H:%M:%S) UTC)"
debootstrap --variant=minbase bookworm "$R" http://deb.debian.org/debian >"$R.debootstrap.log" 2>&1 \
  || { echo "fresh_debian: debootstrap failed, see $R.debootstrap.log" >&2; exit 1; }
mount -t proc proc "$R/proc"
mount --rbind /dev "$R/dev"
mount --rbind /sys "$R/sys"
cp /etc/resolv.conf "$R/etc/resolv.conf"
git clone -q "$ROOT" "$R/root/tessera"
in_root() { chroot "$R" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin "$@"; }
in_root bash -c 'apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq git ca-certificates >/dev/null'
echo "fresh_debian: scripts/$WHAT.sh in the fresh root ($(date -u +%H:%M:%S) UTC, load: $(cut -d' ' -f1-3 /proc/loadavg))"
start=$SECONDS
in_root bash -c "cd /root/tessera && scripts/$WHAT.sh"
echo "fresh_debian: scripts/$WHAT.sh passed in $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s" \
  "(load at the end: $(cut -d' ' -f1-3 /proc/loadavg))"
