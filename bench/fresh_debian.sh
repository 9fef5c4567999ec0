#!/usr/bin/env bash
# Measures `./setup.sh run` on a fresh Debian 12 (README, "A newcomer's first
# run"): a minimal bookworm root made by debootstrap, entered with chroot, in
# which setup.sh installs every package it needs, builds pd_app and runs the
# default example. Prints the package install's and the whole command's wall
# times. Needs root, network access to deb.debian.org and about 3 GB.
#
#   bench/fresh_debian.sh DIR    DIR must not exist; it is made and kept
set -euo pipefail

[[ $# -eq 1 ]] || { sed -n '2,9s/^# \{0,1\}//p' "$0" >&2; exit 2; }
root=$1
[[ ! -e $root ]] || { echo "fresh_debian.sh: $root exists; give a new folder" >&2; exit 1; }
[[ $(id -u) -eq 0 ]] || { echo "fresh_debian.sh: debootstrap and chroot need root" >&2; exit 1; }
command -v debootstrap >/dev/null || apt-get install -y debootstrap
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

debootstrap --variant=minbase bookworm "$root" http://deb.debian.org/debian >"$root.debootstrap.log" 2>&1
cp /etc/resolv.conf "$root/etc/resolv.conf"
printf 'deb http://deb.debian.org/debian bookworm-updates main\ndeb http://deb.debian.org/debian-security bookworm-security main\n' \
  >>"$root/etc/apt/sources.list"
git clone -q "$here" "$root/root/peri"
mount -t proc proc "$root/proc"
mount --rbind /dev "$root/dev"
trap 'umount -l "$root/proc" "$root/dev"' EXIT

chroot "$root" /bin/bash -c '
  export HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin
  cd /root/peri
  start=$(date +%s)
  ./setup.sh run >/root/setup_run.log 2>&1
  end=$(date +%s)
  installed=$(date -d "$(grep End-Date /var/log/apt/history.log | tail -1 | cut -d" " -f2-)" +%s)
  echo "package install: $((installed - start)) s; ./setup.sh run in all: $((end - start)) s (log: /root/setup_run.log)"'
