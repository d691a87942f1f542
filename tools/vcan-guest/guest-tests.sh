#!/bin/sh
# The vcan checks, run inside the qemu guest by /init (or natively by run.sh on a host that has
# vcan0 up). Needs on PATH: stickslip, test_socketcan, can-utils (cangen, candump, canplayer,
# cansend) and `timeout`. Every command runs under `timeout`. Exit status 0 when every check
# passes; each check prints "check: NAME: ok" or "check: NAME: FAILED".
set -u
iface="${STICKSLIP_VCAN_IFACE:-vcan0}"
out="${VCAN_OUT:-/tmp/vcan-out}"
mkdir -p "$out"
failures=0

check() {  # check NAME COMMAND... (sh has no locals: the check_ names are this function's own)
  check_name="$1"; shift
  check_start=$(cut -d' ' -f1 /proc/uptime)
  if "$@"; then
    echo "check: $check_name: ok ($check_start -> $(cut -d' ' -f1 /proc/uptime) s)"
  else
    echo "check: $check_name: FAILED (status $?)"
    failures=$((failures + 1))
  fi
}

# 1. The SocketCAN transport against the real kernel (CppUTest), incl. cansend -> our receive
#    and our send -> candump.
socketcan_group() {
  STICKSLIP_VCAN_IFACE="$iface" STICKSLIP_VCAN_DOWN_IFACE="${STICKSLIP_VCAN_DOWN_IFACE:-vcan9}" \
    timeout 300 test_socketcan -v -sg "$1"
}
check "CppUTest SocketCanWithoutInterface" socketcan_group SocketCanWithoutInterface
check "CppUTest SocketCanVcan" socketcan_group SocketCanVcan

echo "VCAN-GUEST: $failures failed check(s)"
[ "$failures" -eq 0 ]
