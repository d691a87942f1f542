#!/usr/bin/env bash
# The soak run: 1e9 samples (11.6 days of ride at 1 ms) of the lorry-like scene through the
# Observer as the ECU node runs it (model step, 10 s block window, exponential window, regime
# tracker, Wk ride comfort, and the whole-stream statistics beside it), in float (the ECU's type),
# checking no NaN/Inf in any output, integer time keeping (t = n dt, every count exact, every
# window block where the count says) and every statistic against a recomputation from the same
# samples in long double (see reliability/src/soak_main.cpp). About 3 min per 1e9 samples on an
# idle core (--path oscillator: the oscillator and its statistics only, about 1 min).
#   tools/soak.sh [--samples N] [--type float|double] [--path observer|oscillator] [--update-docs]
# Checkpoints go to build/soak/soak-<type>.csv (soak-oscillator-<type>.csv for the oscillator
# path) and, with gnuplot (install-deps.sh --report), the figure build/soak/soak-<type>.png; with
# --update-docs to docs/reliability/ and docs/img/ instead, the committed files that
# docs/RELIABILITY.md shows (the float run through the observer), so that a trial run never
# rewrites them.
set -euo pipefail
cd "$(dirname "$0")/.."
samples=1e9
type=float
path=observer
update_docs=0
while [ $# -gt 0 ]; do
  case "$1" in
    --samples) samples=$2; shift 2 ;;
    --type) type=$2; shift 2 ;;
    --path) path=$2; shift 2 ;;
    --update-docs) update_docs=1; shift ;;
    *) echo "soak: unknown option '$1' (--samples N, --type float|double, --path observer|oscillator, --update-docs)" >&2; exit 2 ;;
  esac
done
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target stickslip_soak
if [ "$update_docs" = 1 ]; then
  csv_dir=docs/reliability
  png_dir=docs/img
else
  csv_dir=build/soak
  png_dir=build/soak
fi
mkdir -p "$csv_dir" "$png_dir"
name=$([ "$path" = observer ] && echo "soak-$type" || echo "soak-oscillator-$type")
csv=$csv_dir/$name.csv
build/release/reliability/stickslip_soak --samples "$samples" --type "$type" --path "$path" --csv "$csv"
if command -v gnuplot >/dev/null 2>&1; then
  # Every difference over its own tolerance (1 = the check's limit): the whole stream's T_ax and p
  # (256 ulp), and for the observer the worst so far of its window (per_block + blocks ulp),
  # exponential window and comfort (their bounds, see soak_main.cpp).
  tolerance=$([ "$type" = float ] && echo 3.0517578125e-5 || echo 5.684341886080802e-14)
  lines="\"$csv\" every ::1 using 1:(\$6 > 0 ? \$6 / $tolerance : 1e-9) with linespoints title \"T_{ax}, whole stream\", \"$csv\" every ::1 using 1:(\$7 > 0 ? \$7 / $tolerance : 1e-9) with linespoints title \"p, whole stream\""
  if [ "$path" = observer ]; then
    lines="$lines, \"$csv\" every ::1 using 1:8 with linespoints title \"window (worst so far)\", \"$csv\" every ::1 using 1:9 with linespoints title \"exponential window (worst so far)\", \"$csv\" every ::1 using 1:10 with linespoints title \"ride comfort (worst so far)\""
  fi
  gnuplot <<PLOT
set terminal pngcairo size 1000,420 font ",10"
set output "$png_dir/$name.png"
set datafile separator ","
set key outside right
set logscale xy
set yrange [1e-7:10]
set format x "10^{%T}"
set format y "10^{%T}"
set xlabel "samples (1 ms each)"
set ylabel "difference / tolerance"
set title "Soak ($path, $type): statistics against a recomputation from the same samples in long double"
plot $lines, 1 with lines dashtype 2 title "tolerance"
PLOT
fi
echo "soak: wrote $csv$([ "$update_docs" = 1 ] || echo " (--update-docs writes docs/reliability/)")" >&2
