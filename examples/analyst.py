#!/usr/bin/env python3
"""An analyst's session with the stickslip module: a recording, a K sweep, signum against
stick-slip, the paper's Fig. 6 (T_ax against Den Hartog's K) and ride comfort.

    PYTHONPATH=build/release/python python3 examples/analyst.py --out-dir /tmp/seat-study

Writes into --out-dir only: the recording (recording.csv, unless --recording names one),
sweep.csv, summary.md and the figures fig6-t_ax-vs-k.png, time-history.png, ride-comfort.png.
"""

import argparse
import csv
import math
import os
import tempfile

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import stickslip  # noqa: E402

SEAT = dict(mass=88.4, stiffness=11500.0)  # the paper's seat; b = 504 N s/m or 0
A0U = 0.35  # m/s^2, RMS of the cab floor


def friction_for(k, mass, rms_u):
    """F_fk that gives Den Hartog's K = 4 F_fk / (pi sqrt(2) m a0u)."""
    return k * math.pi * math.sqrt(2.0) * mass * rms_u / 4.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out-dir", help="where every file goes (default: a fresh temp dir)")
    parser.add_argument("--recording", help="CSV, .mat or candump .log (default: generated)")
    parser.add_argument("--duration", type=float, default=120.0, help="generated recording, s")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = parser.parse_args()
    out_dir = args.out_dir or tempfile.mkdtemp(prefix="stickslip-analyst-")
    os.makedirs(out_dir, exist_ok=True)

    # 1. The recording: the paper's wide-band excitation, saved as the command writes it and
    #    loaded back as any recording would be.
    path = args.recording
    if path is None:
        rec = stickslip.generate("wideband", rms=A0U, duration=args.duration, dt=1e-3, seed=1)
        path = os.path.join(out_dir, "recording.csv")
        np.savetxt(path, np.column_stack([rec["t"], rec["a_u"]]), delimiter=",", fmt="%.17g",
                   header="t,a_u", comments="")
    rec = stickslip.read_recording(path)
    a_u, dt = rec["a_u"], rec["dt"]
    rms_u = float(np.sqrt(np.mean(a_u ** 2)))
    print(f"recording {path}: {len(a_u)} samples, dt = {dt} s, RMS a_u = {rms_u:.4f} m/s^2")

    # 2. The K sweep: F_fk = F_fs from K, stick-slip (exact) against the paper's cheap signum
    #    model (Simulink's ode1; symplectic Euler at b = 0, where ode1 is unstable), at b = 504
    #    and b = 0, all on the cores with simulate_batch.
    ks = np.round(np.arange(0.0, 2.0001, 0.05), 2)
    methods = {"stick-slip": dict(model="stick-slip"),
               "signum (ode1)": dict(model="signum", integrator="euler")}
    runs = []
    for damping in (504.0, 0.0):
        for name, method in methods.items():
            if damping == 0.0 and name == "signum (ode1)":
                method = dict(model="signum", integrator="symplectic")
            for k in ks:
                runs.append(((damping, name, k), dict(SEAT, damping=damping,
                                                      ffk=friction_for(k, SEAT["mass"], rms_u),
                                                      **method)))
    results = stickslip.simulate_batch(a_u, dt, [p for _, p in runs], threads=args.threads,
                                       trace=False)
    table = [dict(damping=key[0], model=key[1], K=stats["K"], ffk=stats["ffk"],
                  T_ax=stats["T_ax"], p_stick=stats["p_stick"], seat=stats["seat"],
                  seat_weighted_rms=stats["seat_weighted_rms"], vdv=stats["vdv"],
                  mtvv=stats["mtvv"], crest_factor=stats["crest_factor"])
             for (key, _), (_, stats) in zip(runs, results)]
    with open(os.path.join(out_dir, "sweep.csv"), "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)

    def curve(damping, model, key):
        rows = [r for r in table if r["damping"] == damping and r["model"] == model]
        return np.array([r["K"] for r in rows]), np.array([r[key] for r in rows])

    # 3. Fig. 6 (b = 504) and Fig. 7 (b = 0): T_ax and p against K.
    figure, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    for column, damping in enumerate((504.0, 0.0)):
        for model in methods:
            k, t_ax = curve(damping, model, "T_ax")
            axes[0, column].plot(k, t_ax, marker=".", label=model)
        k, p = curve(damping, "stick-slip", "p_stick")
        axes[1, column].plot(k, p, marker=".", color="C0", label="stick-slip")
        axes[0, column].set_title(f"b = {damping:g} N s/m")
        axes[0, column].set_ylabel("T_ax = RMS(a_x)/RMS(a_u)")
        axes[1, column].set_ylabel("stick probability p")
        axes[1, column].set_xlabel("Den Hartog's K")
        for row in (0, 1):
            axes[row, column].axvspan(0.4, 0.75, color="0.9", zorder=0)
            axes[row, column].grid(True, alpha=0.3)
        axes[0, column].legend()
    figure.suptitle("T_ax and p against K (shaded: the transition band 0.4 < K < 0.75)")
    figure.tight_layout()
    figure.savefig(os.path.join(out_dir, "fig6-t_ax-vs-k.png"), dpi=110)
    plt.close(figure)

    # 4. Signum against stick-slip in time, at K = 1.3 (the seat should stick most of the time).
    ffk = friction_for(1.3, SEAT["mass"], rms_u)
    shown = slice(0, min(len(a_u), int(round(1.5 / dt)) + 1))
    signum, signum_stats = stickslip.simulate(a_u, dt, model="signum", integrator="euler",
                                              damping=504, ffk=ffk, **SEAT)
    sticky, sticky_stats = stickslip.simulate(a_u, dt, model="stick-slip", damping=504, ffk=ffk,
                                              **SEAT)
    figure, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    t = sticky["t"][shown]
    axes[0].plot(t, sticky["a_u"][shown], color="0.6", label="a_u (cab floor)")
    axes[0].plot(t, signum["a_x"][shown], linewidth=0.5, label="a_x signum (ode1)")
    axes[0].plot(t, sticky["a_x"][shown], label="a_x stick-slip")
    axes[0].set_ylabel("m/s^2")
    axes[1].plot(t, 1e3 * signum["x_r"][shown], label="signum (ode1)")
    axes[1].plot(t, 1e3 * sticky["x_r"][shown], label="stick-slip")
    axes[1].set_ylabel("x_r, mm")
    axes[2].plot(t, signum["f_f"][shown], linewidth=0.5, label="signum (ode1)")
    axes[2].plot(t, sticky["f_f"][shown], label="stick-slip")
    axes[2].fill_between(t, -ffk, ffk, where=sticky["stuck"][shown], color="C2", alpha=0.3,
                         label="stick-slip stuck")
    axes[2].set_ylabel("F_f, N")
    axes[2].set_xlabel("t, s")
    for axis in axes:
        axis.legend(loc="upper right")
        axis.grid(True, alpha=0.3)
    figure.suptitle(f"K = {sticky_stats['K']:.2f}: signum T_ax = {signum_stats['T_ax']:.3f}, "
                    f"stick-slip T_ax = {sticky_stats['T_ax']:.3f} (p = "
                    f"{sticky_stats['p_stick']:.2f})")
    figure.tight_layout()
    figure.savefig(os.path.join(out_dir, "time-history.png"), dpi=110)
    plt.close(figure)

    # 5. Ride comfort (ISO 2631-1, Wk) against K: SEAT, VDV and the crest factor.
    figure, axes = plt.subplots(1, 3, figsize=(13, 4))
    for model in methods:
        for axis, key, label in zip(axes, ("seat", "vdv", "crest_factor"),
                                    ("SEAT = a_w,seat / a_w,floor", "VDV, m/s^1.75",
                                     "crest factor")):
            k, values = curve(504.0, model, key)
            axis.plot(k, values, marker=".", label=model)
            axis.set_ylabel(label)
            axis.set_xlabel("Den Hartog's K")
            axis.grid(True, alpha=0.3)
    axes[0].legend()
    figure.suptitle("Ride comfort at b = 504 N s/m")
    figure.tight_layout()
    figure.savefig(os.path.join(out_dir, "ride-comfort.png"), dpi=110)
    plt.close(figure)

    # 6. A short summary: where signum stops being good enough.
    lines = ["| K | T_ax stick-slip | T_ax signum (ode1) | signum error | p | SEAT stick-slip |",
             "|---|---|---|---|---|---|"]
    k_axis, t_stick = curve(504.0, "stick-slip", "T_ax")
    _, t_signum = curve(504.0, "signum (ode1)", "T_ax")
    _, p = curve(504.0, "stick-slip", "p_stick")
    _, seat = curve(504.0, "stick-slip", "seat")
    for i in range(0, len(k_axis), 4):
        error = 100.0 * (t_signum[i] - t_stick[i]) / t_stick[i]
        lines.append(f"| {k_axis[i]:.2f} | {t_stick[i]:.3f} | {t_signum[i]:.3f} | {error:+.1f} % "
                     f"| {p[i]:.2f} | {seat[i]:.3f} |")
    with open(os.path.join(out_dir, "summary.md"), "w") as file:
        file.write(f"Recording {os.path.basename(path)}, RMS a_u = {rms_u:.4f} m/s^2, "
                   f"b = 504 N s/m\n\n" + "\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"files in {out_dir}")


if __name__ == "__main__":
    main()
