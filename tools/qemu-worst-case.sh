#!/usr/bin/env bash
# The firmware's worst frame on the hardest input set, checked against a stated limit: generates the
# hostile recording (stickslip_node_hardest_input: the seat held at its break-away threshold,
# mixed with full-range jumps and swings of the limit force), runs it on QEMU through tools/qemu-compare.sh (bit for bit against
# the host build as well) and fails if a target's worst frame exceeds its limit.
#   tools/qemu-worst-case.sh [--seat reference|end-stops] STICKSLIP REPLAY_DIR CROSS_ROOT WORK_DIR
#                            [SECONDS (600)]
# --seat end-stops: the firmware built with the seat of docs/scenes/seat-with-end-stops.toml
# (stickslip_firmware_qemu_end_stops.elf) on the hardest set for that seat
# (stickslip_node_hardest_input --end-stops: driven into its stops, held at its break-away
# threshold there).
# REPLAY_DIR holds stickslip_node_replay_* and stickslip_node_hardest_input (host build).
# Prints qemu-compare.sh's lines, then one line per target: "worst PRESET max=N limit=L ok|OVER",
# for the Cortex-M0+ followed by "median_floor=M ratio_to_median_floor=ok|OVER" (worst <= 5 M;
# with end stops ok|missed, reported and not checked), then "bound=B within_bound=ok|OVER": the
# static bound of tools/elf-wcet.py on the same ELF and interrupt as qemu-compare.sh checks it,
# for a frame that follows no gap (max_gap=0; the set is replayed over the loopback bus, so every
# frame brings one sample, which the check confirms from the frames sent). A measured frame above
# the bound means the analysis or its loop bounds are wrong.
set -euo pipefail

# Instructions per frame (QEMU -icount, the whole CAN receive interrupt: node and step) that the
# hardest set's worst frame may take. These are regression limits, up to 5 % above what this code
# measures on the set (docs/EMBEDDED.md, "Bound on the work of one step"), not the targets of
# 4,000 (Cortex-M0+) and 600 (Cortex-M4F) instructions, which the step does not meet. QEMU's count
# is deterministic, so the same ELFs measure the same figures on every machine.
# Cortex-M0+ (Q7.24, one tick per step, the cubic search, at most 3 events, and a stage of the
# statistics window): 9,600 measured (its worst frame is a step with events in a frame that also
# sends SeatStats and SeatScene).
readonly kLimitM0plus=10080
# Cortex-M4F (float, one tick per step for this seat, Taylor/Newton inside it, and the observer's
# window): 3,680 measured.
readonly kLimitM4f=3860
# The Cortex-M0+ target that is met: the worst frame at most 5 times the median, taken at the
# lower edge of the median's 100-instruction bucket (the smallest the median can be).
readonly kMaxRatioM0plus=5

# The seat with end stops, on its own hardest set (--seat end-stops): Cortex-M0+ 22,960 measured,
# Cortex-M4F 22,520 (steps of several events at a stop, a release and a new contact among them;
# in float every advance() measures x_r from the stop's edge, models/end_stops.hpp anchor_of()).
readonly kLimitM0plusEndStops=24100
readonly kLimitM4fEndStops=23640

seat_kind=reference
if [ "${1:-}" = "--seat" ]; then
  seat_kind=${2:-}
  shift 2 || true
fi
case $seat_kind in
  reference) hardest_options=() limit_m0plus=$kLimitM0plus limit_m4f=$kLimitM4f ;;
  end-stops)
    hardest_options=(--end-stops)
    limit_m0plus=$kLimitM0plusEndStops limit_m4f=$kLimitM4fEndStops
    ;;
  *) echo "qemu-worst-case: --seat takes reference or end-stops, got '$seat_kind'" >&2; exit 2 ;;
esac
stickslip=$1 replay_dir=$2 cross_root=$3 work=$4 seconds=${5:-600}
here=$(dirname "$(realpath "$0")")
mkdir -p "$work"
"$replay_dir/stickslip_node_hardest_input" "$seconds" "$work/hardest.csv" "${hardest_options[@]}"
status=0
"$here/qemu-compare.sh" --seat "$seat_kind" "$stickslip" "$replay_dir" "$cross_root" "$work/qemu" \
  "$work/hardest.csv" >"$work/qemu.txt" || status=1
cat "$work/qemu.txt"
while read -r preset _ _ rest; do
  case $preset in cortex-*) ;; *) continue ;; esac  # the end-stop run's contacts line
  max=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "instructions_per_frame_max" {print $2}')
  p50=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "instructions_per_frame_p50" {print $2}')
  target=${preset%_end_stops}
  limit=$limit_m4f
  [ "$target" = cortex-m0plus ] && limit=$limit_m0plus
  verdict=ok
  if [ -z "$max" ] || [ "$max" -gt "$limit" ]; then
    verdict=OVER
    status=1
  fi
  ratio="" median_floor=""
  if [ "$target" = cortex-m0plus ]; then
    median_floor=$((${p50:-100} - 100))
    if [ -z "$max" ] || [ "$median_floor" -le 0 ] || [ "$max" -gt $((kMaxRatioM0plus * median_floor)) ]; then
      # The end-stop seat misses the ratio (8.0x, docs/EMBEDDED.md): reported, not a failure.
      if [ "$seat_kind" = reference ]; then
        ratio=" ratio_to_median_floor=OVER"
        status=1
      else
        ratio=" ratio_to_median_floor=missed"
      fi
    else
      ratio=" ratio_to_median_floor=ok"
    fi
    ratio=" median_floor=$median_floor$ratio"
  fi
  frames=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "frames" {print $2}')
  sent=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "frames_sent" {print $2}')
  # The static bound and its check are qemu-compare.sh's; the bound after no gap holds only if
  # every frame brought one sample: SeatMotion and SeatForce per frame, and (--outputs full)
  # SeatStats and SeatScene with the first sample and every tenth after it.
  bound=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "bound" {print $2}')
  within=$(tr ' ' '\n' <<<"$rest" | awk -F= '$1 == "within_bound" {print $2}')
  expected=$((2 * ${frames:-0} + 2 * ((${frames:-0} + 9) / 10)))
  if [ "$within" != ok ] || [ "${sent:-0}" -ne "$expected" ]; then
    within=OVER
    status=1
  fi
  echo "worst $preset max=${max:-none} limit=$limit $verdict$ratio bound=${bound:-none} within_bound=$within"
done <"$work/qemu.txt"
exit $status
