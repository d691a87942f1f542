#!/usr/bin/env bash
# Runs the firmware's ECU node on QEMU (Cortex-M0+ build, Q7.24 fixed point, on mps2-an385;
# Cortex-M4F build, float, on mps2-an386) on the frames of a candump log, and compares the CAN
# frames it sends (SeatMotion/SeatForce/SeatStats/SeatScene of docs/can/stickslip.dbc) byte for
# byte with the same lib/ node built for the host, and with the frames the host `ecu` node sends
# over the loopback bus (`stickslip replay --outputs full`) for the same log: --scalar float for
# the M4F, --scalar fixed32 for the M0+. The step records (the model's outputs, bit for bit) are
# compared too.
#   tools/qemu-compare.sh [--seat reference|end-stops] STICKSLIP REPLAY_DIR CROSS_ROOT WORK_DIR [CSV]
# --seat end-stops: the firmware built with the seat of docs/scenes/seat-with-end-stops.toml
# (stickslip_firmware_qemu_end_stops.elf, STICKSLIP_FIRMWARE_END_STOPS) against the host node
# running that scene (`--scene`); the host run must reach the stops, or the check fails. Every
# frame must stay within the build's static bound (tools/elf-wcet.py), or the check fails.
# STICKSLIP: the host `stickslip` command; REPLAY_DIR: holds stickslip_node_replay_fixed and
# _float (host build; _end_stops for --seat end-stops); CROSS_ROOT: holds cortex-m0plus/ and
# cortex-m4f/ build trees; CSV: the recording (default: 10 s of the lorry scene, generated, at
# 0.35 m/s^2 RMS, or 5 m/s^2 for the seat with end stops, which then meets its stops about a dozen
# times). The candump log is
# `stickslip replay --output-log` of the CSV: its SeatInput frames (E2E fields) are fed to the
# firmware, its host node's output frames are the reference. Prints, per target, the frames sent
# and compared, the mismatching frames, whether the records are identical, and the instructions
# per received frame (mean, percentiles as the upper edge of their 100-instruction bucket, and
# max, counted by QEMU with -icount shift=0; the index of the slowest frame, to trace it with
# -singlestep -d exec), the deepest stack the CAN receive interrupt reached (painted stack) and
# the static bound per frame with whether every frame stayed within it. Exit status 1 on any
# difference or a frame over the bound.
set -euo pipefail

source_dir=$(cd "$(dirname "$0")/.." && pwd)
seat_kind=reference
if [ "${1:-}" = "--seat" ]; then
  seat_kind=${2:-}
  shift 2 || true
fi
case $seat_kind in
  reference) variant="" rms=0.35 ;;
  end-stops) variant=_end_stops rms=5 ;;
  *) echo "qemu-compare: --seat takes reference or end-stops, got '$seat_kind'" >&2; exit 2 ;;
esac
stickslip=$(realpath "$1") replay_dir=$(realpath "$2") cross_root=$(realpath "$3") work=$4
csv=${5:-}
mkdir -p "$work"
work=$(realpath "$work")
if [ -z "$csv" ]; then
  csv=$work/recording.csv
  "$stickslip" generate --kind lorry --rms $rms --duration 10 --dt 0.001 --seed 1 --output "$csv" >/dev/null
fi
# The firmware's seat and node (port/baremetal/src/node.cpp) as the host `ecu` node runs them:
# float with the observer (the M4F build), Q7.24 with its window over its words (the M0+ build).
# With end stops, the scene's seat (node.cpp states the same parameters).
if [ "$seat_kind" = end-stops ]; then
  seat=(--scene "$source_dir/docs/scenes/seat-with-end-stops.toml" --integrator exact
    --input-range 32.768 --displacement-range 0.1)
else
  seat=(--model stick-slip --ffk 45 --ffs 45 --integrator exact --input-range 32.768
    --displacement-range 0.1)
fi
"$stickslip" replay --input "$csv" --bus loopback --output "$work/ecu.csv" \
  --output-log "$work/input.log" "${seat[@]}" --scalar float --outputs full >"$work/ecu.json"
"$stickslip" replay --input "$csv" --bus loopback --output "$work/ecu-fixed32.csv" \
  --output-log "$work/input-fixed32.log" "${seat[@]}" --scalar fixed32 --outputs full \
  >"$work/ecu-fixed32.json"

if [ "$seat_kind" = end-stops ]; then
  contacts=()
  for json in "$work/ecu.json" "$work/ecu-fixed32.json"; do
    contacts+=("$(tail -n 1 "$json" | python3 -c 'import json, sys; print(json.load(sys.stdin)["end_stop_contacts"])')")
    if ! [ "${contacts[-1]}" -gt 0 ]; then
      echo "qemu-compare: $json: the seat never met its end stops; the check would prove nothing" >&2
      exit 1
    fi
  done
  echo "end_stop_contacts float=${contacts[0]} fixed=${contacts[1]}"
fi

# candump lines "(time) iface ID#DATA" -> 16-byte frame records (port/baremetal/src/replay.hpp):
# every frame to feed the node, and the ecu node's own output frames to compare with.
records() {  # LOG FED.bin SENT.bin
  python3 - "$@" <<'PY'
import re, struct, sys
outputs = {0x180, 0x181, 0x182, 0x183}
with open(sys.argv[1]) as log, open(sys.argv[2], "wb") as fed, open(sys.argv[3], "wb") as sent:
    for number, line in enumerate(log, 1):
        m = re.match(r"\s*\(\S+\)\s+\S+\s+([0-9A-Fa-f]+)#([0-9A-Fa-f]*)\s*$", line)
        if not m:
            sys.exit(f"{sys.argv[1]}:{number}: not a candump data frame: {line.strip()}")
        ident, data = int(m.group(1), 16), bytes.fromhex(m.group(2))
        if len(m.group(1)) > 3 or len(data) > 8:
            sys.exit(f"{sys.argv[1]}:{number}: extended id or CAN FD frame: not in this log")
        record = struct.pack("<IBBxx", ident, len(data), 0) + data.ljust(8, b"\0")
        # The node's controller filters on SeatInput: other nodes' outputs are not delivered
        # (the node would count them as ignored_output), so every interrupt is one input frame.
        if ident in outputs:
            sent.write(record)
        else:
            fed.write(record)
PY
}
records "$work/input.log" "$work/stickslip-input.bin" "$work/ecu-frames-float.bin"
records "$work/input-fixed32.log" "$work/stickslip-input-fixed32.bin" "$work/ecu-frames-fixed.bin"
# Both runs fed the node the same SeatInput frames.
cmp -s "$work/stickslip-input.bin" "$work/stickslip-input-fixed32.bin" ||
  { echo "qemu-compare: the two replays wrote different SeatInput frames" >&2; exit 1; }

status=0
run_target() {  # preset machine scalar
  local preset=$1 machine=$2 scalar=$3
  local dir=$work/$preset
  mkdir -p "$dir"
  cp "$work/stickslip-input.bin" "$dir/"
  (cd "$dir" && timeout 600 qemu-system-arm -M "$machine" -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native -icount shift=0 \
      -kernel "$cross_root/$preset/port/baremetal/stickslip_firmware_qemu$variant.elf") >"$dir/qemu.txt" 2>&1
  "$replay_dir/stickslip_node_replay_$scalar$variant" "$dir/stickslip-input.bin" "$dir/host-frames.bin" \
    "$dir/host-records.bin"
  local frames sent mismatched records mean max stack against_ecu=""
  frames=$(awk '$1 == "frames" {print $2}' "$dir/qemu.txt")
  mean=$(awk '$1 == "instructions_per_frame_mean" {print $2}' "$dir/qemu.txt")
  max=$(awk '$1 == "instructions_per_frame_max" {print $2}' "$dir/qemu.txt")
  p50=$(awk '$1 == "instructions_per_frame_p50" {print $2}' "$dir/qemu.txt")
  p99=$(awk '$1 == "instructions_per_frame_p99" {print $2}' "$dir/qemu.txt")
  p999=$(awk '$1 == "instructions_per_frame_p999" {print $2}' "$dir/qemu.txt")
  worst_frame=$(awk '$1 == "worst_frame_index" {print $2}' "$dir/qemu.txt")
  stack=$(awk '$1 == "callback_stack_bytes" {print $2}' "$dir/qemu.txt")
  # Frames compared record by record: the count and the ones that differ.
  read -r sent mismatched < <(python3 - "$dir/stickslip-frames.bin" "$dir/host-frames.bin" <<'PY'
import sys
a, b = (open(p, "rb").read() for p in sys.argv[1:3])
n = max(len(a), len(b)) // 16
print(len(a) // 16, sum(a[16 * i:16 * i + 16] != b[16 * i:16 * i + 16] for i in range(n)))
PY
)
  if [ "$sent" -gt 0 ] && [ "$mismatched" -eq 0 ] && cmp -s "$dir/host-frames.bin" "$dir/stickslip-frames.bin"; then
    frames_verdict=identical
  else
    frames_verdict=DIFFERENT
    status=1
  fi
  if cmp -s "$dir/host-records.bin" "$dir/stickslip-records.bin"; then
    records=identical
  else
    records=DIFFERENT
    status=1
  fi
  if cmp -s "$work/ecu-frames-$scalar.bin" "$dir/stickslip-frames.bin"; then
    against_ecu=" frames_against_ecu_loopback=identical"
  else
    against_ecu=" frames_against_ecu_loopback=DIFFERENT"
    status=1
  fi
  # The build's static bound (tools/elf-wcet.py, a frame after no gap: the log holds one sample
  # per frame) must hold every measured frame, or the analysis is wrong.
  local bound bound_check
  bound=$(python3 "$source_dir/tools/elf-wcet.py" \
    "$cross_root/$preset/port/baremetal/stickslip_firmware_qemu$variant.elf" CAN0_IRQHandler \
    --bounds "$source_dir/port/baremetal/loop-bounds.json" --target "$preset" --set max_gap=0 \
    --bound-only) || bound=""
  if [ -n "$bound" ] && [ -n "$max" ] && [ "$max" -le "$bound" ]; then
    bound_check=" bound=$bound within_bound=ok"
  else
    bound_check=" bound=${bound:-none} within_bound=OVER"
    status=1
  fi
  echo "$preset$variant $machine $scalar frames=$frames frames_sent=$sent frames_mismatched=$mismatched frames_verdict=$frames_verdict records=$records$against_ecu instructions_per_frame_mean=$mean instructions_per_frame_p50=$p50 instructions_per_frame_p99=$p99 instructions_per_frame_p999=$p999 instructions_per_frame_max=$max worst_frame_index=$worst_frame callback_stack_bytes=$stack$bound_check"
}
run_target cortex-m0plus mps2-an385 fixed
run_target cortex-m4f mps2-an386 float
exit $status
