"""An actuator force f_a (N) runs in Python as in the command: a file's column, an array, a step."""

import numpy as np
import pytest

import stickslip
from conftest import cli_error, cli_simulate, run_cli
from test_simulate_matches_cli import assert_same_run

# Two rates and seeds, each a 10 s lorry floor with a 1.1 Hz push of 30 N amplitude: about a
# third of the reference seat's 88.4 kg at 0.35 m/s^2, so that the force changes the run.
RECORDINGS = [(0.001, 2), (0.0005, 7)]

CASES = [
    # (simulate's keyword arguments, the command's flags)
    (dict(model="stick-slip", ffk=40, ffs=55), ["--model", "stick-slip", "--ffk", 40, "--ffs", 55]),
    (dict(model="signum", ffk=40, integrator="euler"),
     ["--model", "signum", "--ffk", 40, "--integrator", "euler"]),
    (dict(model="stick-slip", ffk=40, scalar="float"),
     ["--model", "stick-slip", "--ffk", 40, "--scalar", "float"]),
    (dict(model="stick-slip", ffk=40, scalar="fixed"),
     ["--model", "stick-slip", "--ffk", 40, "--scalar", "fixed"]),
    (dict(model="stick-slip", ffk=40, integrator="reference"),
     ["--model", "stick-slip", "--ffk", 40, "--integrator", "reference"]),
]


def write_forced(path, t, a_u, f_a):
    """A t,a_u,f_a CSV whose numbers round-trip (%.17g), as the command reads it."""
    np.savetxt(path, np.column_stack([t, a_u, f_a]), fmt="%.17g", delimiter=",",
               header="t,a_u,f_a", comments="")


@pytest.fixture(scope="module", params=RECORDINGS,
                ids=[f"dt={dt},seed={seed}" for dt, seed in RECORDINGS])
def forced_csv(request, cli, tmp_path_factory):
    dt, seed = request.param
    directory = tmp_path_factory.mktemp("forced")
    floor = directory / "floor.csv"
    run_cli(cli, "generate", "--kind", "lorry", "--rms", 0.35, "--duration", 10, "--dt", dt,
            "--seed", seed, "--output", floor)
    table = np.loadtxt(floor, delimiter=",", skiprows=1, dtype=np.float64)
    t = table[:, 0]
    path = directory / "forced.csv"
    write_forced(path, t, table[:, 1], 30.0 * np.sin(2.0 * np.pi * 1.1 * t))
    return path


@pytest.mark.parametrize("arguments,flags", CASES, ids=[str(c[0]) for c in CASES])
def test_force_column_of_a_file_gives_the_commands_forced_run(cli, forced_csv, tmp_path,
                                                              arguments, flags):
    cli_trace, cli_stats = cli_simulate(cli, forced_csv, tmp_path, *flags)
    trace, stats = stickslip.simulate(str(forced_csv), **arguments)
    assert_same_run(trace, stats, cli_trace, cli_stats)


def test_force_column_changes_the_run(forced_csv):
    recording = stickslip.read_recording(forced_csv)
    forced, _ = stickslip.simulate(str(forced_csv), ffk=40)
    passive, _ = stickslip.simulate(recording["a_u"], recording["dt"], ffk=40)
    # F_L = f_a - m a_u - k x_r: the push moves the seat against the frame.
    assert np.max(np.abs(forced["x_r"] - passive["x_r"])) > 1e-3


def test_force_array_gives_the_run_of_the_files_column(forced_csv):
    recording = stickslip.read_recording(forced_csv)
    table = np.loadtxt(forced_csv, delimiter=",", skiprows=1, dtype=np.float64)
    assert np.array_equal(recording["f_a"], table[:, 2])
    from_file, file_stats = stickslip.simulate(str(forced_csv), ffk=40, ffs=55)
    from_arrays, array_stats = stickslip.simulate(recording["a_u"], recording["dt"], ffk=40,
                                                  ffs=55, f_a=recording["f_a"])
    for name in ("x_r", "v_r", "a_x", "f_f", "stuck"):
        assert np.array_equal(from_arrays[name], from_file[name]), name
    assert array_stats["input"] == ""
    for key in set(file_stats) - {"input", "ns_per_sample"}:
        assert array_stats[key] == file_stats[key], key


def test_recording_without_a_force_column_has_no_f_a(lorry_csv):
    assert "f_a" not in stickslip.read_recording(lorry_csv)


def test_batch_with_a_force_equals_single_forced_calls(forced_csv):
    recording = stickslip.read_recording(forced_csv)
    params_list = [dict(ffk=20), dict(ffk=40, ffs=55), dict(model="signum", ffk=40)]
    runs = stickslip.simulate_batch(recording["a_u"], recording["dt"], params_list, threads=2,
                                    f_a=recording["f_a"])
    for (trace, stats), params in zip(runs, params_list):
        single, single_stats = stickslip.simulate(recording["a_u"], recording["dt"],
                                                  f_a=recording["f_a"], **params)
        assert np.array_equal(trace["a_x"], single["a_x"])
        assert stats["T_ax"] == single_stats["T_ax"]


@pytest.mark.parametrize("params", [dict(model="stick-slip", ffk=40),
                                    dict(model="stick-slip", ffk=40, scalar="float"),
                                    dict(model="smooth", ffk=40)],
                         ids=["stick-slip", "stick-slip float", "smooth"])
def test_oscillator_stepped_with_a_force_equals_the_forced_simulate(forced_csv, params):
    recording = stickslip.read_recording(forced_csv)
    a_u, f_a, dt = recording["a_u"][:3000], recording["f_a"][:3000], recording["dt"]
    trace, _ = stickslip.simulate(a_u, dt, f_a=f_a, **params)
    seat = stickslip.Oscillator(dt, **params)
    seat.reset(0.0, 0.0, a_u[0], f_a0=f_a[0])
    rows = [seat.current(f_a=f_a[0])]
    rows += [seat.step(a, f_a=f) for a, f in zip(a_u[1:100], f_a[1:100])]
    for name in ("x_r", "v_r", "a_x", "f_f", "stuck"):
        stepped = np.array([getattr(row, name) for row in rows])
        assert np.array_equal(stepped, trace[name][:100]), name
    rest = seat.run(a_u[100:], f_a=f_a[100:])
    for name in ("x_r", "v_r", "a_x", "f_f", "stuck"):
        assert np.array_equal(rest[name], trace[name][100:]), name


def test_force_array_must_match_the_samples_and_be_finite(lorry_csv):
    with pytest.raises(ValueError, match=r"^f_a: 3 forces for the 4 samples of a_u"):
        stickslip.simulate(np.zeros(4), 0.001, f_a=np.zeros(3))
    with pytest.raises(ValueError, match=r"^f_a = inf at sample 2: simulate needs finite samples"):
        stickslip.simulate(np.zeros(4), 0.001, f_a=[0.0, 1.0, np.inf, 0.0])
    with pytest.raises(ValueError, match=r"^f_a: a recording file gives its own actuator force"):
        stickslip.simulate(str(lorry_csv), f_a=np.zeros(4))
    seat = stickslip.Oscillator(0.001)
    with pytest.raises(ValueError, match=r"^f_a: expected a 1-D array of forces"):
        seat.run(np.zeros(4), f_a=np.zeros(3))


def test_float_run_refuses_a_force_beyond_float_range_as_the_command_does(cli, tmp_path):
    path = tmp_path / "huge.csv"
    write_forced(path, [0.0, 0.001, 0.002], [0.0, 0.1, 0.0], [0.0, 1e300, 0.0])
    message = cli_error(cli, "simulate", "--input", path, "--output", tmp_path / "o.csv",
                        "--model", "stick-slip", "--scalar", "float")
    assert "f_a = 1e+300 at t = 0.001 s is beyond the range of a float" in message
    with pytest.raises(ValueError, match=r"^f_a = \S+ at sample 1 is beyond the range of a float"):
        stickslip.simulate(str(path), model="stick-slip", scalar="float")


def test_logger_text_with_units_and_a_force_gives_the_commands_run(cli, forced_csv, tmp_path):
    # Tab-separated, a_u in g, the time column by its unit: the command's text reader, not the
    # t,a_u CSV's, so simulate(path) must read through the command's own path to agree.
    table = np.loadtxt(forced_csv, delimiter=",", skiprows=1, dtype=np.float64)
    path = tmp_path / "logger.txt"
    np.savetxt(path, np.column_stack([table[:, 0], table[:, 1] / 9.80665, table[:, 2]]),
               fmt="%.17g", delimiter="\t", header="time [s]\ta_u [g]\tf_a [N]", comments="")
    flags = ["--model", "stick-slip", "--ffk", 40]
    cli_trace, cli_stats = cli_simulate(cli, path, tmp_path, *flags)
    trace, stats = stickslip.simulate(str(path), model="stick-slip", ffk=40)
    assert_same_run(trace, stats, cli_trace, cli_stats)
    assert np.array_equal(stickslip.read_recording(path)["f_a"], table[:, 2])
