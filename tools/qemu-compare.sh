#!/usr/bin/env bash
# Runs the firmware's node on QEMU (Cortex-M0+ build, fixed point, on mps2-an385; Cortex-M4F
# build, float, on mps2-an386) with a recording fed through the CAN receive callback, and compares
# every step's outputs byte for byte with the same node built for the host.
#   tools/qemu-compare.sh STICKSLIP REPLAY_DIR CROSS_ROOT WORK_DIR [CSV]
# STICKSLIP: the host `stickslip` command; REPLAY_DIR: holds stickslip_node_replay_fixed and
# _float (host build); CROSS_ROOT: holds cortex-m0plus/ and cortex-m4f/ build trees; CSV: the
# recording (default: 10 s of the lorry scene, generated). Prints, per target, the frames, whether
# they are identical, and the instructions per frame (mean, percentiles as the upper edge of
# their 100-instruction bucket, and max, counted by QEMU with
# -icount shift=0) and the deepest stack the CAN receive interrupt reached (painted stack). Exit status 1 on any difference.
set -euo pipefail

stickslip=$(realpath "$1") replay_dir=$(realpath "$2") cross_root=$(realpath "$3") work=$4
csv=${5:-}
mkdir -p "$work"
work=$(realpath "$work")
if [ -z "$csv" ]; then
  csv=$work/recording.csv
  "$stickslip" generate --kind lorry --rms 0.35 --duration 10 --dt 0.001 --seed 1 --output "$csv" >/dev/null
fi
# The CAN payload: int16 a_u in mm/s^2, little endian (node.hpp).
LC_ALL=C awk -F, 'NR > 1 && NF >= 2 {
    v = $2 * 1000; r = v < 0 ? -int(-v + 0.5) : int(v + 0.5)
    if (r > 32767) r = 32767; if (r < -32767) r = -32767
    if (r < 0) r += 65536
    printf "%c%c", r % 256, int(r / 256)
  }' "$csv" >"$work/stickslip-input.bin"

status=0
run_target() {  # preset machine scalar
  local preset=$1 machine=$2 scalar=$3
  local dir=$work/$preset
  mkdir -p "$dir"
  cp "$work/stickslip-input.bin" "$dir/"
  (cd "$dir" && timeout 600 qemu-system-arm -M "$machine" -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native -icount shift=0 \
      -kernel "$cross_root/$preset/port/baremetal/stickslip_firmware_qemu.elf") >"$dir/qemu.txt" 2>&1
  "$replay_dir/stickslip_node_replay_$scalar" "$dir/stickslip-input.bin" "$dir/host.bin"
  local frames mean max stack verdict
  frames=$(awk '$1 == "frames" {print $2}' "$dir/qemu.txt")
  mean=$(awk '$1 == "instructions_per_frame_mean" {print $2}' "$dir/qemu.txt")
  max=$(awk '$1 == "instructions_per_frame_max" {print $2}' "$dir/qemu.txt")
  p50=$(awk '$1 == "instructions_per_frame_p50" {print $2}' "$dir/qemu.txt")
  p99=$(awk '$1 == "instructions_per_frame_p99" {print $2}' "$dir/qemu.txt")
  p999=$(awk '$1 == "instructions_per_frame_p999" {print $2}' "$dir/qemu.txt")
  stack=$(awk '$1 == "callback_stack_bytes" {print $2}' "$dir/qemu.txt")
  if cmp -s "$dir/host.bin" "$dir/stickslip-output.bin"; then
    verdict=identical
  else
    verdict=DIFFERENT
    status=1
  fi
  echo "$preset $machine $scalar frames=$frames $verdict instructions_per_frame_mean=$mean instructions_per_frame_p50=$p50 instructions_per_frame_p99=$p99 instructions_per_frame_p999=$p999 instructions_per_frame_max=$max callback_stack_bytes=$stack"
}
run_target cortex-m0plus mps2-an385 fixed
run_target cortex-m4f mps2-an386 float
exit $status
