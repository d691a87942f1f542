#!/usr/bin/env bash
# Writes docs/SCENES.md: what each scene effect costs per sample (median ns/sample over
# repetitions, and instructions/sample under callgrind) against a hand-written linear oscillator,
# from bench/scene/bench_scene.cpp on this machine.
#   tools/scene-costs.sh        (about 3 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh --report
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target stickslip_bench_scene
bench=build/release/bench/scene/stickslip_bench_scene
work=build/release/scene-costs
rm -rf "$work" && mkdir -p "$work/callgrind"
"$bench" --benchmark_repetitions=7 --benchmark_report_aggregates_only=true \
  --benchmark_enable_random_interleaving=true \
  --benchmark_out="$work/timing.json" --benchmark_out_format=json >/dev/null
# The target's ratio (linear scene against the hand-written loop, double) moves by up to 25 %
# from one process to the next on a shared 2-core VM, far more than within one, so it is taken
# in 7 separate processes and the report states their median and each one's.
for run in 1 2 3 4 5 6 7; do
  "$bench" --benchmark_filter='^scene/double/(hand-written-linear|spring\+damper)$' \
    --benchmark_repetitions=7 --benchmark_report_aggregates_only=true \
    --benchmark_enable_random_interleaving=true \
    --benchmark_out="$work/linear-$run.json" --benchmark_out_format=json >/dev/null
done
names=$("$bench" --benchmark_list_tests=true)
for name in $names; do
  tag=${name//\//_}
  valgrind --tool=callgrind --callgrind-out-file="$work/callgrind/$tag.cg" \
    --toggle-collect='*run_hand_written*' --toggle-collect='*run_model*' \
    "$bench" --benchmark_filter="^${name//+/\\+}\$" --benchmark_min_time=0.000001 \
    --benchmark_out="$work/callgrind/$tag.json" --benchmark_out_format=json >/dev/null 2>"$work/callgrind/$tag.log"
done
python3 tools/scene_costs_report.py "$work" docs/SCENES.md "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo "wrote docs/SCENES.md" >&2
