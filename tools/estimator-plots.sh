#!/bin/sh
# The state estimator's validation figures for docs/IDENTIFICATION.md: runs the validation program
# (per seed and floor level, Markdown table on stdout, kept in BUILD/estimator/table.md) and plots
# one run's trace (floor RMS 0.6 m/s^2, seed 1) with gnuplot into docs/img/.
#
#   tools/estimator-plots.sh [BUILD_DIR]     (default build/release; needs the target
#                                            stickslip_estimator_validation and gnuplot)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
out=$build/estimator
mkdir -p "$out" "$root/docs/img"
"$build/reliability/stickslip_estimator_validation" --seeds 5 --trace "$out/trace.dat" \
  --trace-rms 0.6 --trace-seed 1 | tee "$out/table.md"

# Columns of trace.dat: 1 t, 2 v_r, 3 v_hat, 4 x_r, 5 x_hat, 6 F_f, 7 F_f_hat, 8 F_fk, 9 F_fk_hat,
# 10 F_fs, 11 F_fs_hat, 12 stuck, 13 stuck_hat.
gnuplot <<GNUPLOT
set terminal pngcairo size 900,420 font ",10"
set output "$root/docs/img/estimator-friction-levels.png"
set title "Friction levels: truth (drifting +20 % over 100 s) and online estimates (start 45 N)"
set xlabel "t (s)"
set ylabel "force (N)"
set key bottom right
set grid
plot "$out/trace.dat" every 20 using 1:8 with lines lw 2 lc rgb "#1f77b4" title "F_{fk} truth", \
     "" every 20 using 1:9 with lines lc rgb "#ff7f0e" title "F_{fk} estimate", \
     "" every 20 using 1:10 with lines lw 2 lc rgb "#2ca02c" title "F_{fs} truth", \
     "" every 20 using 1:11 with lines lc rgb "#d62728" title "F_{fs} estimate"

set output "$root/docs/img/estimator-zoom.png"
set terminal pngcairo size 900,640 font ",10"
set multiplot layout 2,1 title "a_x + travel, floor RMS 0.6 m/s^2, seed 1, t = 60 .. 60.6 s"
set xrange [60:60.6]
set key top right
unset title
set ylabel "v_r (mm/s)"
plot "$out/trace.dat" using 1:(\$12*0) with lines lc rgb "#bbbbbb" notitle, \
     "" using 1:(1e3*\$2) with lines lw 2 lc rgb "#1f77b4" title "truth", \
     "" using 1:(1e3*\$3) with lines lc rgb "#ff7f0e" title "estimate"
set ylabel "F_f (N)"
set xlabel "t (s)"
plot "$out/trace.dat" using 1:6 with lines lw 2 lc rgb "#1f77b4" title "truth", \
     "" using 1:7 with lines lc rgb "#ff7f0e" title "estimate", \
     "" using 1:(\$12*90-45) with steps lc rgb "#2ca02c" title "stuck (truth)", \
     "" using 1:(\$13*90-47) with steps lc rgb "#d62728" title "stuck (estimate)"
unset multiplot
GNUPLOT
echo "wrote $root/docs/img/estimator-friction-levels.png $root/docs/img/estimator-zoom.png"
