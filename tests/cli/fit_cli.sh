#!/usr/bin/env bash
# `stickslip fit` as a user runs it (the real executable) on rig files written by
# stickslip_fit_validation (reference-solver a_x, 0.02 m/s^2 noise): the estimates and the JSON
# line, the residual PNG, a fit that does not converge, and the bad rig files - each bad one one
# line on stderr, exit status 1 (2 for a request that makes no sense), nothing on stdout.
#   fit_cli.sh STICKSLIP STICKSLIP_FIT_VALIDATION
set -euo pipefail
stickslip=$1
validation=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "fit_cli: $*" >&2; exit 1; }

# Expects exit status $1, an empty stdout and one stderr line containing $2.
refuses() {
  local status=$1 text=$2
  shift 2
  set +e
  "$stickslip" fit "$@" >out.txt 2>err.txt
  local got=$?
  set -e
  [ "$got" = "$status" ] || fail "fit $* exited $got, expected $status: $(cat err.txt)"
  [ ! -s out.txt ] || fail "fit $* printed on stdout: $(head -3 out.txt)"
  [ "$(wc -l <err.txt)" = 1 ] || fail "fit $* wrote $(wc -l <err.txt) lines on stderr: $(cat err.txt)"
  grep -qF -- "$text" err.txt || fail "fit $*: expected '$text' in: $(cat err.txt)"
}

# K = 0.8 (F_fk = 47.1 N, F_fs = 56.6 N), 60 s.
"$validation" --write-rig rig.csv --seed 11 --K 0.8 --duration 60
"$stickslip" fit --input rig.csv --mass 88.4 --plot residual.png >out.txt
/usr/bin/python3 - <<'PY' || fail "the JSON line: $(tail -1 out.txt)"
import json, math
j = json.loads(open("out.txt").read().splitlines()[-1])
ffk = 0.8 * math.pi * math.sqrt(2) * 88.4 * 0.6 / 4
truth = {"stiffness": (11500, 0.02), "damping": (504, 0.02), "ffk": (ffk, 0.03),
         "ffs": (1.2 * ffk, 0.03)}
for key, (value, tolerance) in truth.items():
    assert abs(j[key] / value - 1) <= tolerance, (key, j[key], value)
    assert 0 < j[key + "_ci95"] < tolerance * value, (key, j[key + "_ci95"])
for key in ("rms_residual", "T_ax_measured", "T_ax_model", "p_model", "iterations", "seconds"):
    assert key in j, key
assert j["converged"] is True
assert abs(j["T_ax_model"] / j["T_ax_measured"] - 1) < 0.01, (j["T_ax_model"], j["T_ax_measured"])
assert j["rms_residual"] < 0.025, j["rms_residual"]
assert "mass" not in j  # given, not fitted
PY
grep -q "^  stiffness .* +- .* N/m (95 %" out.txt || fail "no stiffness line: $(cat out.txt)"
grep -q "^correlation of the estimates" out.txt || fail "no correlation matrix: $(cat out.txt)"
[ "$(head -c 8 residual.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
  fail "residual.png is no PNG"
ls | grep -q tmp && fail "a temporary file was left: $(ls)"

# The same file as a logger writes it (units in the header) is read the same.
"$validation" --write-rig units.csv --seed 11 --K 0.8 --duration 60 --unit-header
"$stickslip" fit --input units.csv --mass 88.4 >units.txt
[ "$(tail -1 units.txt | sed 's/"seconds":[^,]*,//')" = "$(tail -1 out.txt | sed 's/"seconds":[^,]*,//')" ] ||
  fail "the file with units in its header fits differently"

# The same rig as a data logger exports it: a banner, semicolons, decimal commas, its own column
# names, both accelerations in g and the travel in mm, every second sample (500 Hz).
# At its own 500 Hz step (the exact integrator runs at any step) it is the same experiment with
# half of the samples, so each estimate must lie within the SI 1 kHz fit's 95 % interval.
# Resampled to 1 kHz (--dt 0.001), a_x's jumps at each stick/slip switch (F/m, about 0.6 m/s^2)
# ring in the band-limited resampler (Gibbs), which raises the residual and moves the estimates
# by several intervals: there the bound is the accuracy the fit is validated to against the
# truth (stickslip_fit_validation: k, b 2 %; F_fk, F_fs 3 %), and docs/IDENTIFICATION.md says to
# fit a logger's file at its own rate.
"$validation" --write-rig travel.csv --seed 11 --K 0.8 --duration 60 --travel
"$stickslip" fit --input travel.csv --mass 88.4 >si.txt
/usr/bin/python3 - <<'PY'
g = 9.80665
rows = [line.split(",") for line in open("travel.csv").read().splitlines()[1:]]
def comma(value):
    return repr(value).replace(".", ",")
with open("logger.txt", "w", newline="", encoding="utf-8") as out:
    out.write("\ufeffLogger export 2026-11-27\r\nChannels: 3\r\n")
    out.write("Zeit [s];Boden [g];Sitz [g];Weg [mm]\r\n")
    for row in rows[::2]:
        t, a_u, a_x, x_r = (float(v) for v in row)
        out.write(";".join([comma(t), comma(a_u / g), comma(a_x / g), comma(x_r * 1e3)]) + "\r\n")
with open("norate.txt", "w") as out:  # no time column, no units: --rate and --*-unit say them
    out.write("floor;seat;travel\n")
    for row in rows[::2]:
        t, a_u, a_x, x_r = (float(v) for v in row)
        out.write(";".join([comma(a_u / g), comma(a_x / g), comma(x_r * 1e3)]) + "\n")
PY
"$stickslip" fit --input logger.txt --mass 88.4 --signal Boden --ax-signal Sitz \
  --travel-signal Weg >logger_fit.txt 2>logger_err.txt
[ ! -s logger_err.txt ] || fail "nothing was done to the samples, yet: $(cat logger_err.txt)"
"$stickslip" fit --input logger.txt --mass 88.4 --signal Boden --ax-signal Sitz \
  --travel-signal Weg --dt 0.001 >resampled_fit.txt 2>resampled_err.txt
[ "$(grep -c "resampled to 1000 Hz" resampled_err.txt)" = 3 ] ||
  fail "expected a resampling line per channel: $(cat resampled_err.txt)"
/usr/bin/python3 - <<'PY' || fail "the logger's fits differ from the SI file's"
import json
def last(name):
    return json.loads(open(name).read().splitlines()[-1])
si, own, resampled = last("si.txt"), last("logger_fit.txt"), last("resampled_fit.txt")
for key, validated in (("stiffness", 0.02), ("damping", 0.02), ("ffk", 0.03), ("ffs", 0.03)):
    for name, fit, bound in (("500 Hz", own, si[key + "_ci95"]),
                             ("resampled to 1 kHz", resampled, validated * si[key])):
        difference = abs(fit[key] - si[key])
        print(f"fit_cli: logger {name} vs SI 1 kHz: {key} {fit[key]:.6g} vs {si[key]:.6g}: "
              f"{difference / si[key + '_ci95']:.2f} x the 95 % interval, "
              f"{100 * difference / si[key]:.3f} %")
        assert difference <= bound, (name, key)
PY
"$stickslip" fit --input norate.txt --mass 88.4 --signal floor --unit g --ax-signal 2 \
  --ax-unit g --travel-signal travel --travel-unit mm --rate 500 >norate_fit.txt
[ "$(tail -1 norate_fit.txt | sed 's/"seconds":[^,]*,//')" = "$(tail -1 logger_fit.txt | sed 's/"seconds":[^,]*,//')" ] ||
  fail "--rate 500 with --unit/--ax-unit/--travel-unit fits differently from the header's units"
# Without any recording flag a logger's export is read as simulate reads it (its time column in
# ms, its units in the header), not refused for want of a column 't'.
/usr/bin/python3 - <<'PY'
g = 9.80665
rows = [line.split(",") for line in open("travel.csv").read().splitlines()[1:]]
def comma(value):
    return repr(value).replace(".", ",")
with open("named.txt", "w") as out:
    out.write("Rig DAQ export\nTime [ms];a_u [g];a_x [mm/s^2];x_r [mm]\n")
    for row in rows[::2]:
        t, a_u, a_x, x_r = (float(v) for v in row)
        out.write(";".join([comma(t * 1e3), comma(a_u / g), comma(a_x * 1e3), comma(x_r * 1e3)]) + "\n")
PY
"$stickslip" fit --input named.txt --mass 88.4 >named_fit.txt 2>named_err.txt ||
  fail "a logger's export without flags: $(cat named_err.txt)"
/usr/bin/python3 - <<'PY' || fail "the logger's export without flags fits differently"
import json
def last(name):
    return json.loads(open(name).read().splitlines()[-1])
named, own = last("named_fit.txt"), last("logger_fit.txt")
for key in ("stiffness", "damping", "ffk", "ffs"):
    # The same samples in other units (ms and mm/s^2 against s and g): each differs by the
    # conversions' rounding, a few 1e-16, which moves the optimum by 1e-14 here (measured 1.7e-14).
    assert abs(named[key] / own[key] - 1) < 1e-12, (key, named[key], own[key])
PY
# The same rig as a vehicle bus carries it: replay --estimator sends a_u in SeatInput and the
# measured a_x and travel in SeatSensors (docs/CAN.md) over the loopback bus, and --output-log
# writes the candump log with the clock's time stamps (seconds since the epoch). Read back with the
# project's DBC, each channel named MESSAGE.SIGNAL, the fit is the same experiment with the
# signals quantised to their frames' resolution (a_u, a_x 2^-10 m/s^2, travel 2^-16 m, far below
# the noise), so each estimate must lie within the SI fit's 95 % interval.
dbc=$source_dir/docs/can/stickslip.dbc
"$stickslip" replay --input travel.csv --estimator --output bus_trace.csv --output-log bus.log \
  --model stick-slip --ffk 47 >/dev/null 2>&1 || fail "replay --estimator of the rig failed"
"$stickslip" fit --input bus.log --dbc "$dbc" --signal SeatInput.a_u --ax-signal SeatSensors.a_x \
  --travel-signal SeatSensors.x_r --mass 88.4 >can_fit.txt 2>can_err.txt ||
  fail "fit of the candump log: $(cat can_err.txt)"
/usr/bin/python3 - <<'PY' || fail "the candump log's fit differs from the SI file's"
import json
def last(name):
    return json.loads(open(name).read().splitlines()[-1])
si, can = last("si.txt"), last("can_fit.txt")
for key in ("stiffness", "damping", "ffk", "ffs"):
    difference = abs(can[key] - si[key])
    print(f"fit_cli: candump log vs SI: {key} {can[key]:.6g} vs {si[key]:.6g}: "
          f"{difference / si[key + '_ci95']:.2f} x the 95 % interval")
    assert difference <= si[key + "_ci95"], key
PY
# Without its first SeatSensors frame the measured channels start a step after a_u: refused.
awk '/ 101#/ && !dropped { dropped = 1; next } { print }' bus.log >late.log
refuses 1 "does not line up with a_u" --input late.log --dbc "$dbc" --signal SeatInput.a_u \
  --ax-signal SeatSensors.a_x --travel-signal SeatSensors.x_r --mass 88.4

# --gaps split: the rig with 1 s lost at t = 30 s is two parts, each simulated from rest at its own
# start, fitted as one least-squares problem. Both parts must be in it with all their samples
# (30000 and 29001: a part dropped changes the counts), each part's residual must stay at the
# noise of the unbroken recording's fit (within 5 %: a model state carried over the gap, i.e. a
# bridged gap, leaves a transient after it; --gaps hold, which bridges by holding, measures
# 0.11 m/s^2 against 0.020), and the estimates must lie within the unbroken fit's 95 % intervals.
awk -F, 'NR == 1 || !($1 >= 30 && $1 < 31)' travel.csv >gapped.csv
"$stickslip" fit --input gapped.csv --mass 88.4 --gaps split >split.txt 2>split_err.txt
[ "$(grep -c "split into 2 segments" split_err.txt)" = 3 ] ||
  fail "expected each channel split in 2: $(cat split_err.txt)"
grep -q "^part from t = 31 s: 29001 samples, rms residual a_x" split.txt ||
  fail "no line for the second part: $(cat split.txt)"
/usr/bin/python3 - <<'PY' || fail "the split fit: $(tail -1 split.txt) against $(tail -1 si.txt)"
import json
def last(name):
    return json.loads(open(name).read().splitlines()[-1])
si, split = last("si.txt"), last("split.txt")
parts = split["segments"]
assert [(p["t_start_s"], p["samples"]) for p in parts] == [(0.0, 30000), (31.0, 29001)], parts
for part in parts:
    assert part["rms_residual"] <= 1.05 * si["rms_residual"], (part, si["rms_residual"])
for key in ("stiffness", "damping", "ffk", "ffs"):
    difference = abs(split[key] - si[key])
    print(f"fit_cli: --gaps split vs unbroken: {key} {split[key]:.6g} vs {si[key]:.6g}: "
          f"{difference / si[key + '_ci95']:.2f} x the 95 % interval")
    assert difference <= si[key + "_ci95"], key
PY
refuses 2 "--ax-unit: 'N' is not g, m/s^2 or mm/s^2" --input norate.txt --mass 88.4 --signal 1 --ax-signal 2 --ax-unit N --rate 500
refuses 1 "no column 'a_x' (the seat acceleration" --input norate.txt --mass 88.4 --signal floor --unit g --rate 500

# Identifiability reported: at K = 0.05 the seat hardly ever sticks, so F_fs is not seen.
"$validation" --write-rig nostick.csv --seed 2 --K 0.05 --duration 30
"$stickslip" fit --input nostick.csv --mass 88.4 >nostick.txt
grep -q "^warning: ffk and ffs cannot be told apart on this recording" nostick.txt ||
  fail "no identifiability warning at K = 0.05: $(cat nostick.txt)"

# A seat that never slips (here: a quiet floor) moves with the floor: nothing in
# a_x depends on k, b or the friction, and the fit says so rather than estimating from nothing.
"$stickslip" generate --kind lorry --rms 0.05 --duration 20 --dt 0.001 --seed 3 --output quiet_floor.csv
"$stickslip" simulate --input quiet_floor.csv --output quiet_rig.csv --model stick-slip --ffk 45 \
  --ffs 55 >/dev/null
refuses 1 "no fitted parameter changes the model's a_x on this recording (the seat stays stuck" \
  --input quiet_rig.csv --mass 88.4

# A harmonic floor has no power below the natural frequency: the unit check has nothing to read
# there and must not take leakage for a gain (it once said "a_u looks like it is in g"). Noise-free
# reference data: the fit finds the seat to near rounding.
"$stickslip" generate --kind harmonic --frequency 1.3 --rms 1.5 --duration 30 --dt 0.001 --seed 1 \
  --output harm_floor.csv
"$stickslip" simulate --input harm_floor.csv --output harm_rig.csv --model stick-slip --ffk 45 \
  --ffs 55 --integrator reference >/dev/null
"$stickslip" fit --input harm_rig.csv --mass 88.4 >harm.txt || fail "harmonic rig: $(cat harm.txt)"
/usr/bin/python3 - <<'PY' || fail "harmonic rig: $(tail -1 harm.txt)"
import json
j = json.loads(open("harm.txt").read().splitlines()[-1])
for key, truth in (("stiffness", 11500), ("damping", 504), ("ffk", 45), ("ffs", 55)):
    assert abs(j[key] / truth - 1) < 1e-9, (key, j[key])
PY

# Bounds that make no sense are the request's mistake (status 2), named.
refuses 2 "--lower ffk=50 is not below --upper ffk=40" --input rig.csv --mass 88.4 --lower ffk=50 --upper ffk=40
refuses 2 "--start ffk=60 lies outside its --lower/--upper bounds" --input rig.csv --mass 88.4 --start ffk=60 --upper ffk=40
refuses 2 "--lower/--upper ffs: with ffk fitted too" --input rig.csv --mass 88.4 --upper ffs=50
refuses 2 "--mass: must be a finite number > 0, got -3" --input rig.csv --mass -3
# A mass the model cannot take: the refusal names the parameter and its range, not only "every
# start value".
refuses 1 "the model refuses every start value (at the automatic start: mass_kg: must be >= 1e-06 and <= 1e+09 kg, got 1e+12)" \
  --input rig.csv --mass 1e12
# An estimate held by its bound is reported as the bound, not as a minimum.
"$stickslip" fit --input rig.csv --mass 88.4 --upper ffk=40 >bound.txt
grep -q "^warning: ffk ended on its bound" bound.txt || fail "no bound warning: $(cat bound.txt)"

# A 20 Hz hum of 0.1 m/s^2 in a_x (a vibration the seat model lacks, hardly seen by the white-noise
# estimate from second differences) leaves a residual near 4 times the noise: the fit says that
# the model does not fit to the noise; the same rig without the hum does not.
/usr/bin/python3 - <<'PY'
import math
lines = open("rig.csv").read().splitlines()
header = lines[0].split(",")
column = header.index("a_x")
with open("hum.csv", "w") as out:
    out.write(lines[0] + "\n")
    for line in lines[1:]:
        cells = line.split(",")
        t = float(cells[0])
        cells[column] = repr(float(cells[column]) + 0.1 * math.sin(2 * math.pi * 20 * t))
        out.write(",".join(cells) + "\n")
PY
"$stickslip" fit --input hum.csv --mass 88.4 >hum.txt
grep -q "^warning: the rms residual .* times the white noise in a_x" hum.txt ||
  fail "no misfit warning with a hum in a_x: $(cat hum.txt)"
if grep -q "^warning: the rms residual" out.txt; then
  fail "a misfit warning on the rig without the hum: $(cat out.txt)"
fi

# Not converged: says so, status 1, no estimates.
refuses 1 "the fit did not converge after 1 iterations" --input rig.csv --mass 88.4 --max-iterations 1

# Bad rig files.
"$validation" --write-rig no_ax.csv --seed 11 --K 0.8 --duration 20 --no-ax
refuses 1 "no column 'a_x' (the seat acceleration" --input no_ax.csv --mass 88.4
"$validation" --write-rig g_named.csv --seed 11 --K 0.8 --duration 20 --ax-in-g --unit-header
refuses 1 "column 'a_x' is in g but the fit needs m/s^2; multiply it by 9.80665" --input g_named.csv --mass 88.4
"$validation" --write-rig g_unnamed.csv --seed 11 --K 0.8 --duration 60 --ax-in-g
refuses 1 "a_x looks like it is in g, not m/s^2" --input g_unnamed.csv --mass 88.4
"$validation" --write-rig late.csv --seed 11 --K 0.8 --duration 60 --shift-samples 40
refuses 1 "a_x is shifted by 40 samples (40 ms, late) against a_u: where the seat sticks a_x equals a_u" \
  --input late.csv --mass 88.4
# A shift of 5 samples: the fitted model's best lag stays under 3 samples here (the fit bends its
# parameters to the shift: k 8 % low, F_fs on F_fk), but the stuck phases show it, either way.
"$validation" --write-rig late5.csv --seed 11 --K 0.8 --duration 60 --shift-samples 5
refuses 1 "a_x is shifted by 5 samples (5 ms, late) against a_u" --input late5.csv --mass 88.4
"$validation" --write-rig early.csv --seed 12 --K 1.5 --duration 30 --shift-samples -30
refuses 1 "a_x is shifted by 30 samples (30 ms, early) against a_u" --input early.csv --mass 88.4
# The wrong model on aligned channels is a misfit, reported as one, not a shift: the linear seat
# on a stick-slip rig (its best lag against the measured a_x is 7 samples).
"$validation" --write-rig aligned.csv --seed 11 --K 0.8 --duration 20
"$stickslip" fit --input aligned.csv --mass 88.4 --model linear >linear.txt 2>linear_err.txt ||
  fail "linear model on a stick-slip rig: $(cat linear_err.txt)"
grep -q "the model does not fit this recording to its noise" linear.txt linear_err.txt ||
  fail "linear model on a stick-slip rig: expected the misfit warning: $(cat linear.txt linear_err.txt)"
refuses 2 "--fit mass: a_u, a_x and x_r fix only k/m, b/m and F/m" --input rig.csv --fit mass,stiffness
refuses 2 "--fit: the linear model has no parameter ffk" --input rig.csv --mass 88.4 --model linear --fit stiffness,ffk
refuses 2 "--mass: the seat's mass (kg) is needed" --input rig.csv
refuses 2 "--start ffs=50 is below --start ffk=60: the static friction is at least the kinetic" --input rig.csv --mass 88.4 --start ffk=60 --start ffs=50
refuses 2 "--fit: ffk is not fitted, so the model needs its value: give --start ffk=VALUE" --input rig.csv --mass 88.4 --fit stiffness,damping
refuses 2 "--fit: stribeck-velocity is not fitted, so the model needs its value" --input rig.csv --mass 88.4 --model stribeck --fit stiffness,damping,ffk,ffs
refuses 2 "--fit: unknown parameter 'friction'" --input rig.csv --mass 88.4 --fit stiffness,friction
echo "fit_cli: all checks passed"
