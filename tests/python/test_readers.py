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
