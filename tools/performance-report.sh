#!/usr/bin/env bash
# Writes docs/PERFORMANCE.md, docs/performance/results.csv and docs/img/pareto-*.png from scratch:
# installs what the report needs, builds the release preset, counts instructions per sample under
# callgrind, runs the speed/accuracy harness with its Boost.Odeint peers, profiles the headline
# configuration, runs the step benchmark if it is built, writes the report and draws the plots;
# tools/closed-loop-cost-report.sh then appends the closed loop's cost per sample.
#   tools/performance-report.sh        (about 5 minutes on 2 cores; nothing to edit by hand after)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
started=$(date +%s)
stage() { echo "== [$(($(date +%s) - started)) s] $*" >&2; }
# The commit measured, before this script writes anything into the tree.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ -n "$(git status --porcelain 2>/dev/null)" ]; then commit="$commit with uncommitted changes"; fi

bash tools/install-deps.sh --report
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"

build=build/release
harness="$build/bench/tradeoff/stickslip_tradeoff"
bench_step="$build/bench/step/stickslip_bench_step"
work="$build/performance-report"  # scratch: callgrind dumps, profile, facts, plot data
instruction_steps=4000
rm -rf "$work"
mkdir -p "$work/callgrind" "$work/profile" "$work/plot" docs/performance docs/img

stage "instructions per sample: every combination once under callgrind"
valgrind --tool=callgrind --collect-atstart=no --log-file="$work/callgrind.log" \
  --callgrind-out-file="$work/callgrind/cg.%p" \
  "$harness" count-instructions --steps "$instruction_steps"

stage "timed runs, errors against the reference, Boost.Odeint peers"
load_before=$(cut -d' ' -f1 /proc/loadavg)
"$harness" run --instructions "$work/callgrind" --output docs/performance/results.csv
load_after=$(cut -d' ' -f1 /proc/loadavg)

stage "profile: stick-slip / exact / double on lorry-K0.8-b504 at 1 ms, the whole scene"
valgrind --tool=callgrind --collect-atstart=no --log-file="$work/profile.log" \
  --callgrind-out-file="$work/profile/cg.%p" \
  "$harness" count-instructions --kinds lorry --frictions coulomb --K 0.8 --damping 504 \
  --models stick-slip --integrators exact --scalars double --dt 1 --steps 0
profile_dump=$(grep -l "Client Request" "$work"/profile/cg.* | head -n 1 || true)

if [ -x "$bench_step" ]; then
  stage "step benchmark: batch vs singles, and the headline stream"
  "$bench_step" --benchmark_filter='^(batch|singles)/|^stream/double/stick-slip/exact/' \
    --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_out="$work/bench_step.json" --benchmark_out_format=json \
    >"$work/bench_step.txt" 2>&1 || echo "(stickslip_bench_step exited with status $?)" >>"$work/bench_step.txt"
fi

if [ -x "$bench_step" ]; then
  stage "batch profile: instructions per lane-step of batch and singles under callgrind"
  mkdir -p "$work/batch-profile"
  for name in batch/double/N8/own-inputs singles/double/N8/own-inputs \
              batch/float/N16/own-inputs singles/float/N16/own-inputs; do
    tag=${name//\//_}
    valgrind --tool=callgrind --log-file="$work/batch-profile/$tag.log" \
      --callgrind-out-file="$work/batch-profile/$tag.cg" \
      --toggle-collect='*run_batch*' --toggle-collect='*run_stream*' \
      "$bench_step" --benchmark_filter="^$name\$" --benchmark_min_time=0.000001 \
      --benchmark_out="$work/batch-profile/$tag.json" --benchmark_out_format=json >/dev/null
    callgrind_annotate --inclusive=no "$work/batch-profile/$tag.cg" >"$work/batch-profile/$tag.txt"
  done
  if grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo; then
    stage "batch vs singles built for AVX2 (-DSTICKSLIP_ARCH=x86-64-v3, a separate build tree)"
    if cmake -S . -B build/avx2 -DCMAKE_BUILD_TYPE=Release -DSTICKSLIP_ARCH=x86-64-v3 \
         -DSTICKSLIP_BUILD_TESTS=OFF >/dev/null &&
       cmake --build build/avx2 -j "$(nproc)" --target stickslip_bench_step >/dev/null; then
      build/avx2/bench/step/stickslip_bench_step --benchmark_filter='^(batch|singles)/' \
        --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
        --benchmark_out="$work/bench_step_avx2.json" --benchmark_out_format=json >/dev/null 2>&1 ||
        echo "(AVX2 stickslip_bench_step exited with status $?)" >&2
    fi
  fi
fi

bench_estimator="$build/bench/estimator/stickslip_bench_state_estimator"
if [ -x "$bench_estimator" ]; then
  stage "state estimator benchmark: cost per sample against the plain step in the same run"
  "$bench_estimator" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_out="$work/bench_estimator.json" --benchmark_out_format=json \
    >"$work/bench_estimator.txt" 2>&1 || echo "(stickslip_bench_state_estimator exited with status $?)" >&2
fi

{
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(grep -m1 'cpu MHz' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//') MHz as /proc/cpuinfo reports it"
  echo "cores: $(nproc)"
  echo "os: $(. /etc/os-release && echo "$PRETTY_NAME"), Linux $(uname -r)"
  "$harness" build-info
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "commit: $commit"
  echo "instruction steps: $instruction_steps"
  echo "load before: $load_before"
  echo "load after: $load_after"
} >"$work/machine.txt"

stage "report and plots"
"$harness" report --results docs/performance/results.csv --results-link performance/results.csv \
  --machine "$work/machine.txt" --profile-dump "$profile_dump" \
  --bench-step "$work/bench_step.txt" --bench-step-json "$work/bench_step.json" \
  --batch-profile "$work/batch-profile" --bench-step-avx2-json "$work/bench_step_avx2.json" \
  --bench-estimator-json "$work/bench_estimator.json" \
  --output docs/PERFORMANCE.md --plot-dir "$work/plot" --image-link img \
  --command "tools/performance-report.sh" --elapsed "$(($(date +%s) - started))"

stage "closed-loop cost per sample (stickslip_bench_closed_loop), appended to the report"
bash tools/closed-loop-cost-report.sh "$build"

rm -f docs/img/pareto-*.png
(cd "$work/plot" && gnuplot -e "outdir='$root/docs/img'" pareto.gp)
echo "wrote docs/PERFORMANCE.md, docs/performance/results.csv and docs/img/pareto-*.png in $(($(date +%s) - started)) s" >&2
