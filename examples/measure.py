#!/usr/bin/env python3
"""Measures the Python module against the `stickslip` command (docs/PYTHON.md):

  1. cost per sample from Python against the command's own ns_per_sample (its timed loop,
     median of 3 runs) on the same recording: the loop inside simulate() (its ns_per_sample),
     Oscillator.run() over the whole array (wall time), and the whole simulate() call (wall time:
     input copy, loop, fresh trace arrays, the ride-comfort pass, statistics);
  2. simulate_batch's speed-up with 2 threads over 1.

    PYTHONPATH=build/release/python python3 examples/measure.py \
        --cli build/release/sim_host/stickslip --work-dir /tmp/stickslip-measure

Writes only into --work-dir (the recording and the command's output, about 1.6 GB at 1e7).
"""

import argparse
import json
import os
import statistics
import subprocess
import time

import stickslip


def median_wall(call, runs):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True)
    parser.add_argument("--work-dir", required=True)
    parser.add_argument("--samples", type=float, default=1e7)
    parser.add_argument("--batch-samples", type=float, default=1e6)
    parser.add_argument("--batch-runs", type=int, default=8)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    os.makedirs(args.work_dir, exist_ok=True)
    dt = 1e-3
    steps = int(args.samples) - 1
    recording = os.path.join(args.work_dir, "recording.csv")
    subprocess.run([args.cli, "generate", "--kind", "wideband", "--rms", "0.35", "--duration",
                    repr(steps * dt), "--dt", repr(dt), "--seed", "1", "--output", recording],
                   check=True, capture_output=True)
    rec = stickslip.read_recording(recording)
    a_u = rec["a_u"]
    print(f"recording: {len(a_u)} samples (wideband, rms 0.35 m/s^2, dt = {dt} s)")

    for name, params, flags in (
            ("stick-slip exact", dict(model="stick-slip", ffk=45),
             ["--model", "stick-slip", "--ffk", "45"]),
            ("signum euler", dict(model="signum", ffk=45, integrator="euler"),
             ["--model", "signum", "--ffk", "45", "--integrator", "euler"])):
        out = subprocess.run([args.cli, "simulate", "--input", recording, "--output",
                              os.path.join(args.work_dir, "out.csv"), *flags],
                             check=True, capture_output=True, text=True).stdout
        cli_ns = json.loads(out.strip().splitlines()[-1])["ns_per_sample"]
        loop = []

        def call(trace=True):
            _, stats = stickslip.simulate(a_u, rec["dt"], trace=trace, **params)
            loop.append(stats["ns_per_sample"])

        whole = median_wall(call, args.runs) * 1e9 / steps
        no_trace = median_wall(lambda: call(False), args.runs) * 1e9 / steps
        seat = stickslip.Oscillator(dt, **params)

        def run_seat():
            seat.reset(0.0, 0.0, a_u[0])
            seat.run(a_u[1:])

        stepped = median_wall(run_seat, args.runs) * 1e9 / steps
        print(f"{name}: command ns_per_sample {cli_ns:.2f} | Python: the loop inside "
              f"simulate() {statistics.median(loop):.2f} "
              f"({statistics.median(loop) / cli_ns:.2f}x); Oscillator.run() over the array "
              f"{stepped:.2f} ({stepped / cli_ns:.2f}x); the whole simulate() call (new trace "
              f"arrays, ride comfort, statistics) {whole:.2f} ({whole / cli_ns:.2f}x), "
              f"{no_trace:.2f} with trace=False ({no_trace / cli_ns:.2f}x)")

    batch_a_u = a_u[: int(args.batch_samples)]
    params = [dict(model="stick-slip", ffk=5.0 + 10.0 * i) for i in range(args.batch_runs)]
    walls, cores = {}, {}
    for threads in (1, 2):
        before = os.times()
        walls[threads] = median_wall(
            lambda: stickslip.simulate_batch(batch_a_u, dt, params, threads=threads, trace=False),
            args.runs)
        after = os.times()
        # Cores the process actually had: CPU time over wall time (other load shares them).
        cores[threads] = ((after.user + after.system - before.user - before.system) /
                          (after.elapsed - before.elapsed))
    singles = median_wall(lambda: [stickslip.simulate(batch_a_u, dt, trace=False, **p)
                                   for p in params], args.runs)
    print(f"batch: {args.batch_runs} stick-slip runs x {len(batch_a_u)} samples: "
          f"{args.batch_runs} single calls {singles:.3f} s, threads=1 {walls[1]:.3f} s, "
          f"threads=2 {walls[2]:.3f} s: speed-up {walls[1] / walls[2]:.2f}x (cores busy: "
          f"{cores[1]:.2f} with 1 thread, {cores[2]:.2f} with 2; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
