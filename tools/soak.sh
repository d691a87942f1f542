#!/usr/bin/env bash
# The soak run: 1e9 samples (11.6 days of ride at 1 ms) of the lorry-like scene through the
# stick-slip oscillator and its running statistics, in float (the ECU's type), checking no NaN,
# an exact integer sample count and the statistics against a blockwise recomputation (see
# reliability/src/soak_main.cpp). About a minute per 1e9 samples on an idle core.
#   tools/soak.sh [--samples N] [--type float|double]
# Checkpoints go to docs/reliability/soak-<type>.csv and, with gnuplot (install-deps.sh --report),
# the figure docs/img/soak-<type>.png (docs/RELIABILITY.md shows the float run).
set -euo pipefail
cd "$(dirname "$0")/.."
samples=1e9
type=float
while [ $# -gt 0 ]; do
  case "$1" in
    --samples) samples=$2; shift 2 ;;
    --type) type=$2; shift 2 ;;
    *) echo "soak: unknown option '$1' (--samples N, --type float|double)" >&2; exit 2 ;;
  esac
done
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target stickslip_soak
mkdir -p docs/reliability docs/img
csv=docs/reliability/soak-$type.csv
build/release/reliability/stickslip_soak --samples "$samples" --type "$type" --csv "$csv"
if command -v gnuplot >/dev/null 2>&1; then
  tolerance=$([ "$type" = float ] && echo 3.05e-5 || echo 5.68e-14)
  gnuplot <<PLOT
set terminal pngcairo size 900,420 font ",10"
set output "docs/img/soak-$type.png"
set datafile separator ","
set key top left
set logscale xy
set format x "10^{%T}"
set format y "10^{%T}"
set xlabel "samples (1 ms each)"
set ylabel "relative difference, running vs blockwise"
set title "Soak, $type: running statistics against a blockwise long-double recomputation"
plot "$csv" every ::1 using 1:(\$6 > 0 ? \$6 : 1e-17) with linespoints title "T_{ax}", \
     "$csv" every ::1 using 1:(\$7 > 0 ? \$7 : 1e-17) with linespoints title "p", \
     $tolerance with lines dashtype 2 title "tolerance (256 ulp)"
PLOT
fi
