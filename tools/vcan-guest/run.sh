#!/usr/bin/env bash
# The real-kernel vcan test (CTest: vcan.guest, label vcan).
#   run.sh --work DIR --stickslip PATH --test-binary PATH
# Environment: VCAN_DURATION_S (recording replayed over vcan0, default 10 s), VCAN_FULL_DURATION_S
# (the full recording replayed by stickslip replay over vcan0, default 120 s), VCAN_BURST_S
# (cangen burst, default 10 s), VCAN_LOAD_DURATION_S / VCAN_LOAD_SPEED (the load and fault test:
# recording length, default 65 s, played at default 3x), VCAN_LOOP_DURATION_S (the recording of the
# closed loop over vcan0, plant + controller, default 3 s), VCAN_ONLY (only the checks whose name
# contains it), VCAN_QEMU_TIMEOUT (default 600 s).
# Where this host has vcan0 up, runs guest-tests.sh natively. Otherwise builds the guest
# (build-initramfs.sh, cached in DIR) and boots it with qemu-system-x86_64 under TCG; the guest
# runs guest-tests.sh and reports on the serial console and through isa-debug-exit. Passes only
# when both say PASS. Exit 77 (CTest: skipped) when qemu, cpio or depmod are missing (the guest's
# busybox-static, iproute2 and can-utils come from the installed packages or are downloaded).
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
work="" stickslip="" test_binary=""
qemu_timeout="${VCAN_QEMU_TIMEOUT:-600}"
while [ $# -gt 0 ]; do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --stickslip) stickslip="$2"; shift 2 ;;
    --test-binary) test_binary="$2"; shift 2 ;;
    *) echo "run.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -n "$work" ] && [ -x "$stickslip" ] && [ -x "$test_binary" ] || {
  echo "usage: run.sh --work DIR --stickslip PATH --test-binary PATH" >&2; exit 2; }
start_s=$(date +%s.%N)
elapsed() { echo "$(date +%s.%N) $start_s" | awk '{printf "%.1f", $1 - $2}'; }

if [ -r /sys/class/net/vcan0/flags ] && [ $(( $(cat /sys/class/net/vcan0/flags) & 1 )) -eq 1 ]; then
  echo "vcan: this host has vcan0 up: running the checks natively"
  work_bin="$(mktemp -d)"
  trap 'rm -rf "$work_bin"' EXIT
  ln -s "$(cd "$(dirname "$stickslip")" && pwd)/$(basename "$stickslip")" "$work_bin/stickslip"
  ln -s "$(cd "$(dirname "$test_binary")" && pwd)/$(basename "$test_binary")" "$work_bin/test_socketcan"
  mkdir -p "$work/native-out"
  if PATH="$work_bin:$PATH" VCAN_OUT="$work/native-out" STICKSLIP_VCAN_DOWN_IFACE="" \
      timeout 900 sh "$here/guest-tests.sh"; then
    echo "VCAN-GUEST-RESULT: PASS (native, $(elapsed) s)"
    exit 0
  fi
  echo "VCAN-GUEST-RESULT: FAIL (native, $(elapsed) s)"
  exit 1
fi

missing=()
for tool in qemu-system-x86_64 cpio dpkg-deb apt-get depmod ldd; do
  command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "SKIPPED: the vcan guest test needs ${missing[*]} (Debian packages qemu-system-x86, cpio, kmod; tools/install-deps.sh installs them)"
  exit 77
fi

echo "vcan: no vcan0 on this host ($(uname -r)): building the qemu guest in $work"
bash "$here/build-initramfs.sh" --work "$work" --stickslip "$stickslip" --test-binary "$test_binary"
echo "vcan: guest built after $(elapsed) s; booting (TCG, timeout ${qemu_timeout} s)"

# Settings for guest-tests.sh: the kernel hands unknown name=value arguments to /init as
# environment variables.
guest_environment=""
for name in VCAN_DURATION_S VCAN_FULL_DURATION_S VCAN_BURST_S VCAN_LOAD_DURATION_S VCAN_LOAD_SPEED VCAN_LOOP_DURATION_S VCAN_ONLY; do
  [ -n "${!name:-}" ] && guest_environment+=" $name=${!name}"
done
kernel="$work/vmlinuz"
[ -e "$work/vmlinux" ] && kernel="$work/vmlinux"  # PVH boot, no decompression under TCG
serial="$work/serial.log"
rm -f "$serial"
status=0
timeout --kill-after=10 "$qemu_timeout" qemu-system-x86_64 \
  -accel tcg -cpu max -smp 1 -m 768 \
  -nodefaults -nographic -no-reboot -monitor none -serial "file:$serial" \
  -kernel "$kernel" -initrd "$work/initramfs.cpio" \
  -append "console=ttyS0 quiet loglevel=3 panic=-1 $guest_environment" \
  -device isa-debug-exit,iobase=0xf4,iosize=0x04 </dev/null || status=$?
# The guest's console, without the firmware's terminal escapes.
tr -d '\r' < "$serial" | sed 's/\x1b\[[0-9;?]*[a-zA-Z]//g; s/\x1bc//g'
echo
echo "vcan: qemu exit status $status after $(elapsed) s"
if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
  echo "VCAN-GUEST-RESULT: FAIL (qemu timed out after ${qemu_timeout} s)"
  exit 1
fi
# isa-debug-exit: status = (value << 1) | 1; the guest writes 0 for a pass.
if [ "$status" -eq 1 ] && grep -q "^VCAN-GUEST-RESULT: PASS" "$serial"; then
  echo "vcan: PASS ($(elapsed) s in all)"
  exit 0
fi
echo "vcan: FAIL"
exit 1
