#!/usr/bin/env bash
# Regenerates the measured section of docs/CONTROL.md (between the control-report markers) and
# docs/img/control-pareto-*.png: every reference controller on the lorry recording and on the
# seat-test inputs EM1..EM9 (EN ISO 7096 / EN 30326 style spectra at the standard's level), with
# `stickslip closed-loop`. Nothing in that section is typed by hand.
#   tools/control-report.sh [path/to/stickslip]     (default: build/release/sim_host/stickslip)
# About 10 s on one core.
set -euo pipefail
cd "$(dirname "$0")/.."
stickslip=${1:-build/release/sim_host/stickslip}
stickslip=$(realpath "$stickslip")
doc=docs/CONTROL.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p docs/img

# The seat of docs/CONTROL.md: the reference seat with stick-slip friction, F_fs > F_fk.
seat=(--model stick-slip --ffk 40 --ffs 55)
# Sensors an ECU has: seat accelerometer noise 0.02 m/s^2 RMS, travel sensor noise 30 um RMS
# quantised to 0.1 mm; the state estimator corrects itself with both.
sensors=(--a-x-noise 0.02 --x-r-noise 3e-5 --x-r-resolution 1e-4 --seed 1)
duration=60
inputs=(lorry EM1 EM2 EM3 EM4 EM5 EM6 EM7 EM8 EM9)
controllers=(skyhook skyhook-semi groundhook groundhook-semi friction-compensation)

for input in "${inputs[@]}"; do
  if [ "$input" = lorry ]; then
    "$stickslip" generate --kind lorry --rms 0.6 --duration "$duration" --dt 0.001 --seed 1 \
      --output "$work/$input.csv" >/dev/null
  else
    "$stickslip" generate --kind "$input" --duration "$duration" --dt 0.001 --seed 1 \
      --output "$work/$input.csv" >/dev/null
  fi
  for controller in passive "${controllers[@]}"; do
    "$stickslip" closed-loop --input "$work/$input.csv" --output "$work/trace.csv" "${seat[@]}" \
      "${sensors[@]}" --controller "$controller" --gain 1500 --force-limit 1000 |
      tail -n 1 >"$work/$input.$controller.json"
  done
done

# The Pareto plots: seat weighted RMS against actuator force RMS over the hook gain, lorry.
for controller in skyhook skyhook-semi; do
  "$stickslip" closed-loop --input "$work/lorry.csv" --output "$work/sweep-$controller.csv" \
    "${seat[@]}" "${sensors[@]}" --controller "$controller" --sweep-gain 0:4000:9 \
    --plot "docs/img/control-pareto-$controller.png" >"$work/sweep-$controller.txt"
done

version=$("$stickslip" --version | head -n 1)
/usr/bin/python3 - "$work" "$doc" "$version" "${inputs[*]}" "${controllers[*]}" <<'PY'
import json, re, sys
work, doc, version, inputs, controllers = sys.argv[1:6]
inputs, controllers = inputs.split(), controllers.split()
def load(i, c):
    with open(f"{work}/{i}.{c}.json") as f:
        return json.load(f)
lines = [
    "<!-- control-report:begin (tools/control-report.sh writes this section; do not edit) -->",
    "",
    f"Measured with `{version}`: 60 s of each input at dt = 1 ms, seat `--model stick-slip "
    "--ffk 40 --ffs 55` (m = 88.4 kg, k = 11500 N/m, b = 504 N s/m), sensors `--a-x-noise 0.02 "
    "--x-r-noise 3e-5 --x-r-resolution 1e-4`, the state estimator as observer, hook gain 1500 "
    "N s/m, semi-active range 0..3000 N s/m, force limit 1000 N, no lag; friction-compensation "
    "feeds 0.8 of the friction estimate forward.",
    "",
    "Seat weighted RMS (ISO 2631-1 Wk) of the passive seat, and of each controller as a ratio to "
    "it (below 1: more comfort); in brackets the actuator force RMS (N):",
    "",
    "| input | passive a_w (m/s^2) | passive SEAT | " + " | ".join(controllers) + " |",
    "|---|---|---|" + "---|" * len(controllers),
]
for i in inputs:
    p = load(i, "passive")["passive"]
    cells = []
    for c in controllers:
        r = load(i, c)
        cells.append(f"{r['seat_weighted_rms_ratio']:.3f} ({r['controlled']['force_rms']:.0f})")
    lines.append(f"| {i} | {p['seat_weighted_rms']:.3f} | {p['seat']:.3f} | " +
                 " | ".join(cells) + " |")
lines += ["", "Travel used (peak |x_r|, mm) and the actuator's mean power (W; negative: it takes "
          "energy out of the seat's relative motion) on the lorry recording:", "",
          "| controller | SEAT | VDV (m/s^1.75) | travel (mm) | force peak (N) | mean power (W) |",
          "|---|---|---|---|---|---|"]
for c in ["passive"] + controllers:
    r = load("lorry", c)
    f = r["controlled"]
    lines.append(f"| {c} | {f['seat']:.3f} | {f['vdv']:.3f} | {1000 * f['travel']:.2f} | "
                 f"{f['force_peak']:.0f} | {f['mean_power']:.3f} |")
lines += ["", "Gain sweeps on the lorry recording (`--sweep-gain 0:4000:9`):", "",
          "![skyhook Pareto](img/control-pareto-skyhook.png)",
          "![skyhook-semi Pareto](img/control-pareto-skyhook-semi.png)", "",
          "<!-- control-report:end -->"]
text = open(doc).read()
section = "\n".join(lines)
pattern = re.compile(r"<!-- control-report:begin.*?<!-- control-report:end -->", re.S)
if not pattern.search(text):
    sys.exit(f"{doc}: no control-report markers")
open(doc, "w").write(pattern.sub(lambda m: section, text))
print(f"{doc}: control report written")
PY
