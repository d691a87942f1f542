#!/usr/bin/env bash
# Where one frame's instructions go: builds the QEMU firmware of a preset with a mark around the
# CAN receive interrupt of frame FRAME (STICKSLIP_PROFILE_FRAME, port/baremetal/CMakeLists.txt),
# replays INPUT (16-byte frame records, as tools/qemu-compare.sh writes them) on QEMU with
# -icount shift=0 and -singlestep, and lets gdb-multiarch turn QEMU's instruction log on at the
# mark before that frame and off at the mark after it. Every other frame runs unlogged, so the
# frame is traced in the state the whole replay led to.
#   tools/qemu-frame-profile.sh [--seat reference|end-stops] PRESET FRAME INPUT WORK_DIR
# PRESET: cortex-m0plus or cortex-m4f; FRAME: the index from 0, as qemu-compare.sh prints it
# (worst_frame_index). Prints "total N" (the interrupt's instructions: the board's own lines
# around the call are left out), "step N" (those from the entry of the seat's step,
# stickslip_seat_step, until it returns to a function outside its call graph) and then,
# costliest first, one line per function: "INSTRUCTIONS<TAB>CALLS<TAB>FUNCTION" (instructions in
# the function itself, without its callees; calls: entries at its first instruction). Exit
# status 1 if the frame was never reached.
set -euo pipefail

seat_kind=reference
if [ "${1:-}" = "--seat" ]; then
  seat_kind=${2:-}
  shift 2 || true
fi
case $seat_kind in
  reference) variant="" ;;
  end-stops) variant=_end_stops ;;
  *) echo "qemu-frame-profile: --seat takes reference or end-stops, got '$seat_kind'" >&2; exit 2 ;;
esac
if [ $# -ne 4 ]; then
  echo "usage: tools/qemu-frame-profile.sh [--seat reference|end-stops] PRESET FRAME INPUT WORK_DIR" >&2
  exit 2
fi
preset=$1 frame=$2 input=$(realpath "$3") work=$4
case $preset in
  cortex-m0plus) machine=mps2-an385 ;;
  cortex-m4f) machine=mps2-an386 ;;
  *) echo "qemu-frame-profile: PRESET is cortex-m0plus or cortex-m4f, got '$preset'" >&2; exit 2 ;;
esac
[[ $frame =~ ^[0-9]+$ ]] || { echo "qemu-frame-profile: FRAME must be an index (0, 1, ...), got '$frame'" >&2; exit 2; }
[ -s "$input" ] || { echo "qemu-frame-profile: $input: no frame records" >&2; exit 2; }
for tool in qemu-system-arm gdb-multiarch arm-none-eabi-nm arm-none-eabi-c++filt; do
  command -v "$tool" >/dev/null ||
    { echo "qemu-frame-profile: $tool is missing (tools/install-deps.sh installs it)" >&2; exit 2; }
done

source_dir=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work"
work=$(realpath "$work")
build=$work/build-$preset
cmake --preset "$preset" -S "$source_dir" -B "$build" -DSTICKSLIP_PROFILE_FRAME="$frame" \
  >"$work/configure.log" 2>&1 || { echo "qemu-frame-profile: configure failed, see $work/configure.log" >&2; exit 1; }
cmake --build "$build" --target "stickslip_firmware_qemu$variant" >"$work/build.log" 2>&1 ||
  { echo "qemu-frame-profile: build failed, see $work/build.log" >&2; exit 1; }
elf=$build/port/baremetal/stickslip_firmware_qemu$variant.elf
mark=$(arm-none-eabi-nm "$elf" | awk '$3 == "board_profile_mark" {print $1}')
[ -n "$mark" ] || { echo "qemu-frame-profile: $elf has no board_profile_mark" >&2; exit 1; }

run=$work/run
rm -rf "$run"
mkdir -p "$run"
cp "$input" "$run/stickslip-input.bin"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
(cd "$run" && exec qemu-system-arm -M "$machine" -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -icount shift=0 -singlestep -D "$run/exec.log" \
  -gdb "tcp:127.0.0.1:$port" -S -kernel "$elf") >"$run/qemu.txt" 2>&1 &
qemu_pid=$!
trap 'kill "$qemu_pid" 2>/dev/null || true' EXIT
# gdb connects once QEMU listens (state 0A in /proc/net/tcp): connecting to probe would let QEMU
# run on when the probe hangs up.
listening() {
  awk -v port=":$(printf '%04X' "$port")" '$2 ~ port"$" && $4 == "0A" {found = 1} END {exit !found}' \
    /proc/net/tcp
}
for _ in $(seq 100); do
  listening && break
  kill -0 "$qemu_pid" 2>/dev/null || break
  sleep 0.1
done
if ! listening; then
  echo "qemu-frame-profile: QEMU did not start its debugger port, see $run/qemu.txt" >&2
  exit 1
fi
cat >"$run/commands.gdb" <<EOF
set pagination off
set confirm off
target remote 127.0.0.1:$port
break *0x$mark
continue
monitor log exec,nochain
continue
monitor log none
kill
quit
EOF
timeout 1800 gdb-multiarch -batch -x "$run/commands.gdb" "$elf" >"$run/gdb.txt" 2>&1 || true
if [ "$(grep -c '^Breakpoint 1, ' "$run/gdb.txt" || true)" -ne 2 ]; then
  echo "qemu-frame-profile: frame $frame was not reached (is INPUT shorter?), see $run/gdb.txt" >&2
  exit 1
fi

python3 "$source_dir/tools/elf-callgraph.py" "$elf" stickslip_seat_step >"$run/step-callgraph.json"
python3 - "$run/exec.log" "$elf" "$run/step-callgraph.json" <<'PY'
import json, re, subprocess, sys
log, elf, graph = sys.argv[1:4]
step_functions = {f["name"] for f in json.load(open(graph))[0]["functions"]}
starts = {}
for line in subprocess.run(["arm-none-eabi-nm", elf], capture_output=True, text=True, check=True).stdout.splitlines():
    parts = line.split()
    if len(parts) == 3 and parts[1] in "tTW":
        starts[parts[2]] = int(parts[0], 16) & ~1
# By address: a constructor's complete and base-object symbols (C1, C2) are one function, and
# QEMU's log may name it by either.
step_starts = {starts[name] for name in step_functions if name in starts}
board = {"board_idle", "board_profile_mark"}
self_count, calls, total, step, in_step = {}, {}, 0, 0, False
pattern = re.compile(r"\[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/[0-9a-f]+\]\s+(\S+)")
with open(log) as trace:
    for line in trace:
        m = pattern.search(line)
        if not m:
            continue
        pc, symbol = int(m.group(1), 16), m.group(2)
        if symbol in board:
            continue
        total += 1
        if symbol == "stickslip_seat_step" and starts.get(symbol) == pc:
            in_step = True
        elif symbol not in step_functions and starts.get(symbol) not in step_starts:
            in_step = False
        step += in_step
        self_count[symbol] = self_count.get(symbol, 0) + 1
        if starts.get(symbol) == pc:
            calls[symbol] = calls.get(symbol, 0) + 1
names = sorted(self_count, key=lambda s: -self_count[s])
demangled = subprocess.run(["arm-none-eabi-c++filt"], input="\n".join(names), capture_output=True,
                           text=True, check=True).stdout.splitlines()
print(f"total {total}")
print(f"step {step}")
for name, readable in zip(names, demangled):
    print(f"{self_count[name]}\t{calls.get(name, 0)}\t{readable}")
PY
