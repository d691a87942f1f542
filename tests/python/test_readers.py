"""The readers and generators give the command's samples."""

import numpy as np
import pytest

import stickslip
from conftest import run_cli


@pytest.mark.parametrize("kind,flags,arguments", [
    ("lorry", ["--rms", 0.35, "--seed", 3], dict(rms=0.35, seed=3)),
    ("wideband", ["--rms", 1.0, "--seed", 2], dict(rms=1.0, seed=2)),
    ("harmonic", ["--rms", 0.5, "--frequency", 2.5], dict(rms=0.5, frequency=2.5)),
    ("EM6", [], dict()),
    ("white", ["--rms", 0.7, "--band-low", 1, "--band-high", 30],
     dict(rms=0.7, band_low=1, band_high=30)),
])
def test_generate_gives_the_commands_samples(cli, tmp_path, kind, flags, arguments):
    path = tmp_path / "g.csv"
    run_cli(cli, "generate", "--kind", kind, "--duration", 5, "--dt", 0.001, *flags,
            "--output", path)
    table = np.loadtxt(path, delimiter=",", skiprows=1, dtype=np.float64)
    generated = stickslip.generate(kind, duration=5, dt=0.001, **arguments)
    assert generated["dt"] == 0.001
    assert np.array_equal(generated["t"], table[:, 0])
    assert np.array_equal(generated["a_u"], table[:, 1])


def test_read_recording_gives_the_csv_columns(lorry_csv):
    recording = stickslip.read_recording(lorry_csv)
    table = np.loadtxt(lorry_csv, delimiter=",", skiprows=1, dtype=np.float64)
    assert np.array_equal(recording["t"], table[:, 0])
    assert np.array_equal(recording["a_u"], table[:, 1])
    assert recording["dt"] == pytest.approx(0.001, rel=1e-12)


def test_candump_log_gives_the_quantised_samples(cli, lorry_csv, tmp_path):
    log = tmp_path / "lorry.log"
    run_cli(cli, "record", "--input", lorry_csv, "--output", log)
    recording = stickslip.read_recording(log, dt=0.001)
    a_u = stickslip.read_recording(lorry_csv)["a_u"]
    # SeatInput carries a_u in steps of 2^-10 m/s^2, rounded half away from zero.
    scaled = a_u * 1024.0
    expected = np.trunc(scaled + np.copysign(0.5, scaled)) / 1024.0
    assert recording["skipped_frames"] == 0
    assert np.array_equal(recording["a_u"], expected)
    assert np.array_equal(recording["t"], np.arange(len(a_u)) * 0.001)


def test_mat_recording_gives_the_same_run_as_its_csv(lorry_csv, tmp_path):
    scipy_io = pytest.importorskip("scipy.io")
    recording = stickslip.read_recording(lorry_csv)
    mat = tmp_path / "lorry.mat"
    scipy_io.savemat(mat, {"a_u": recording["a_u"], "dt": recording["dt"]})
    from_mat = stickslip.read_recording(mat)
    assert np.array_equal(from_mat["a_u"], recording["a_u"])
    a, _ = stickslip.simulate(str(mat), ffk=45)
    b, _ = stickslip.simulate(from_mat["a_u"], from_mat["dt"], ffk=45)
    assert np.array_equal(a["a_x"], b["a_x"])


def test_den_hartog_factor_is_the_statistics_K(lorry_csv):
    _, stats = stickslip.simulate(str(lorry_csv), ffk=45)
    assert stickslip.den_hartog_factor(45, 88.4, stats["rms_u"]) == stats["K"]


@pytest.mark.parametrize("new_dt", [0.0005, 0.0025, 0.0008])
def test_resample_gives_the_samples_simulate_dt_runs(cli, lorry_csv, tmp_path, new_dt):
    out = tmp_path / "out.csv"
    run_cli(cli, "simulate", "--input", lorry_csv, "--dt", new_dt, "--model", "stick-slip",
            "--ffk", 45, "--repetitions", 1, "--output", out)
    table = np.loadtxt(out, delimiter=",", skiprows=1, dtype=np.float64)
    recording = stickslip.read_recording(lorry_csv)
    resampled = stickslip.resample(recording["a_u"], recording["dt"], new_dt)
    assert resampled["dt"] == new_dt
    assert np.array_equal(resampled["t"], table[:, 0])
    assert np.array_equal(resampled["a_u"], table[:, 1])
    trace, _ = stickslip.simulate(resampled["a_u"], resampled["dt"], model="stick-slip", ffk=45)
    assert np.array_equal(trace["a_x"], table[:, 4])


def test_resampled_recording_runs_a_scene_of_another_rate(cli, source_dir, tmp_path):
    # The lorry scene runs at 1 kHz; the recording is at 400 Hz.
    scene = source_dir / "docs" / "scenes" / "lorry-seat-stick-slip.toml"
    recording = stickslip.generate("lorry", rms=0.35, duration=5, dt=0.0025, seed=4)
    with pytest.raises(ValueError, match=r"resample\(a_u, dt, 0.001\) puts the recording"):
        stickslip.simulate(recording["a_u"], recording["dt"], scene=scene)
    resampled = stickslip.resample(recording["a_u"], recording["dt"], 0.001)
    assert len(resampled["a_u"]) == 5001
    path = tmp_path / "slow.csv"
    np.savetxt(path, np.column_stack([recording["t"], recording["a_u"]]), delimiter=",",
               header="t,a_u", comments="", fmt="%.17g")
    out = tmp_path / "out.csv"
    run_cli(cli, "simulate", "--input", path, "--scene", scene, "--dt", 0.001, "--repetitions", 1,
            "--output", out)
    table = np.loadtxt(out, delimiter=",", skiprows=1, dtype=np.float64)
    trace, _ = stickslip.simulate(resampled["a_u"], resampled["dt"], scene=scene)
    assert np.array_equal(trace["a_x"], table[:, 4])


@pytest.mark.parametrize("arguments,message", [
    ((np.zeros(10), 0.0, 0.001), r"^dt: must be a finite number > 0, got 0$"),
    ((np.zeros(10), 0.001, -1.0), r"^new_dt: must be a finite number > 0, got -1$"),
    ((np.zeros(1), 0.001, 0.002), r"^a_u: resampling needs at least 2 samples, got 1$"),
    ((np.array([0.0, np.nan, 1.0]), 0.001, 0.002),
     r"^a_u = nan at sample 1: resampling needs finite samples$"),
    ((np.zeros(10), 0.001, 1.0),
     r"^new_dt: 1 s leaves 1 of the recording's 10 samples at dt = 0.001 s \(at least 2"),
    (("lorry.csv", 0.001, 0.002), r"^a_u: expected a 1-D array of samples \(m/s\^2\)$"),
])
def test_resample_refuses_bad_arguments_in_one_line(arguments, message):
    with pytest.raises(ValueError, match=message):
        stickslip.resample(*arguments)
