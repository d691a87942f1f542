#!/usr/bin/env bash
# The firmware's instructions per frame are SysTick's count (port/baremetal/src/board_qemu.cpp);
# this checks it against an instruction trace of the same frame (tools/qemu-frame-profile.sh) on
# both targets: the slowest frame of the run tools/qemu-compare.sh left in QEMU_DIR.
#   tests/embedded/trace_matches_systick.sh QEMU_DIR WORK_DIR
# SysTick counts in ticks of 40 instructions: the difference of two readings is the frame's count,
# plus the board's instructions between the two reads (kBoardBetweenReads: the trace leaves them
# out), to within less than one tick either way. So SysTick's count minus the traced count minus
# those 5 must be under 40 in magnitude, or the check fails. It fails as well if the trace holds
# no step, or a step at least as long as the frame.
set -euo pipefail
qemu_dir=$(realpath "$1") work=$2
mkdir -p "$work"
here=$(dirname "$(realpath "$0")")
readonly kTick=40
# The board's instructions from the SysTick read before the interrupt to the one after it, the
# call included: five in board_idle() on both targets (two stores, the call, one more instruction
# and the second read), from the disassembly.
readonly kBoardBetweenReads=5
status=0
for preset in cortex-m0plus cortex-m4f; do
  report=$qemu_dir/$preset/qemu.txt
  index=$(awk '$1 == "worst_frame_index" {print $2}' "$report")
  measured=$(awk '$1 == "instructions_per_frame_max" {print $2}' "$report")
  if [ -z "$index" ] || [ -z "$measured" ]; then
    echo "trace_matches_systick: $report: no worst_frame_index or instructions_per_frame_max" >&2
    exit 1
  fi
  "$here/../../tools/qemu-frame-profile.sh" "$preset" "$index" "$qemu_dir/stickslip-input.bin" \
    "$work/$preset" >"$work/$preset.profile.txt"
  traced=$(awk '$1 == "total" {print $2}' "$work/$preset.profile.txt")
  step=$(awk '$1 == "step" {print $2}' "$work/$preset.profile.txt")
  offset=$((measured - traced - kBoardBetweenReads))
  verdict=ok
  if [ "${offset#-}" -ge "$kTick" ] || [ "$step" -le 0 ] || [ "$step" -ge "$traced" ]; then
    verdict=FAILED
    status=1
  fi
  echo "$preset frame=$index systick=$measured traced=$traced step=$step systick-traced-board=$offset (under $kTick in magnitude) $verdict"
  head -n 8 "$work/$preset.profile.txt" | tail -n 6
done
exit $status
