"""stickslip.simulate runs the command's own loop: the same trace and statistics, bit for bit."""

import numpy as np
import pytest

import stickslip
from conftest import COLUMNS, cli_simulate

# The run figures that measure this machine (ns_per_sample) or name a file the call does not
# write (output) are the only keys allowed to differ.
NOT_COMPARED = {"ns_per_sample", "output"}

CASES = [
    # (simulate's keyword arguments, the command's flags)
    (dict(model="stick-slip", ffk=45), ["--model", "stick-slip", "--ffk", 45]),
    (dict(model="stick-slip", ffk=30, ffs=50, damping=0),
     ["--model", "stick-slip", "--ffk", 30, "--ffs", 50, "--damping", 0]),
    (dict(model="signum", ffk=45, integrator="euler"),
     ["--model", "signum", "--ffk", 45, "--integrator", "euler"]),
    (dict(model="linear"), ["--model", "linear"]),
    (dict(model="smooth", ffk=45, smoothing="atan", smoothing_c=300),
     ["--model", "smooth", "--ffk", 45, "--smoothing", "atan", "--smoothing-c", 300]),
    (dict(model="stribeck", ffk=40, ffs=60, stribeck_velocity=0.02),
     ["--model", "stribeck", "--ffk", 40, "--ffs", 60, "--stribeck-velocity", 0.02]),
    (dict(model="stick-slip", ffk=45, scalar="float"),
     ["--model", "stick-slip", "--ffk", 45, "--scalar", "float"]),
    (dict(model="stick-slip", ffk=45, scalar="fixed"),
     ["--model", "stick-slip", "--ffk", 45, "--scalar", "fixed"]),
    (dict(model="stick-slip", ffk=45, scalar="fixed32", input_range=32.768,
          displacement_range=0.1),
     ["--model", "stick-slip", "--ffk", 45, "--scalar", "fixed32", "--input-range", 32.768,
      "--displacement-range", 0.1]),
    (dict(model="stick-slip", ffk=45, integrator="reference"),
     ["--model", "stick-slip", "--ffk", 45, "--integrator", "reference"]),
    (dict(model="stick-slip", ffk=45, x0=0.01, v0=-0.05),
     ["--model", "stick-slip", "--ffk", 45, "--x0", 0.01, "--v0", -0.05]),
]


def assert_same_run(trace, stats, cli_trace, cli_stats):
    for name in COLUMNS:
        assert np.array_equal(np.asarray(trace[name], dtype=np.float64), cli_trace[name]), name
    assert trace["stuck"].dtype == np.bool_
    for key in set(cli_stats) | set(stats):
        if key not in NOT_COMPARED:
            assert stats.get(key) == cli_stats.get(key), key


@pytest.mark.parametrize("arguments,flags", CASES, ids=[str(c[0]) for c in CASES])
def test_recording_path_gives_the_commands_trace_and_statistics(cli, lorry_csv, tmp_path,
                                                                 arguments, flags):
    cli_trace, cli_stats = cli_simulate(cli, lorry_csv, tmp_path, *flags)
    trace, stats = stickslip.simulate(str(lorry_csv), **arguments)
    assert_same_run(trace, stats, cli_trace, cli_stats)


@pytest.mark.parametrize("arguments,flags", CASES[:3] + CASES[6:9],
                         ids=[str(c[0]) for c in CASES[:3] + CASES[6:9]])
def test_array_of_samples_gives_the_commands_trace_and_statistics(cli, lorry_csv, tmp_path,
                                                                  arguments, flags):
    cli_trace, cli_stats = cli_simulate(cli, lorry_csv, tmp_path, *flags)
    recording = stickslip.read_recording(lorry_csv)
    trace, stats = stickslip.simulate(recording["a_u"], recording["dt"], **arguments)
    assert stats["input"] == ""
    stats["input"] = cli_stats["input"]
    assert_same_run(trace, stats, cli_trace, cli_stats)


@pytest.mark.parametrize("scene", ["lorry-seat-stick-slip.toml", "seat-with-end-stops.toml",
                                   "stribeck-undamped.toml", "linear-seat.toml"])
def test_scene_file_gives_the_commands_run(cli, lorry_csv, tmp_path, source_dir, scene):
    path = source_dir / "docs" / "scenes" / scene
    cli_trace, cli_stats = cli_simulate(cli, lorry_csv, tmp_path, "--scene", path)
    trace, stats = stickslip.simulate(str(lorry_csv), scene=path)
    assert_same_run(trace, stats, cli_trace, cli_stats)


@pytest.mark.parametrize("scalar,integrator",
                         [("fixed", None), ("fixed32", None), ("double", "reference")])
def test_end_stop_scene_in_fixed_point_or_the_reference_gives_the_commands_run(
        cli, hard_csv, tmp_path, source_dir, scalar, integrator):
    path = source_dir / "docs" / "scenes" / "seat-with-end-stops.toml"
    flags = ["--scene", path, "--scalar", scalar]
    arguments = dict(scene=path, scalar=scalar)
    if scalar == "fixed32":
        # Q7.24 holds the scene's 30 N of friction with the firmware's stroke of 0.1 m.
        flags += ["--displacement-range", 0.1]
        arguments["displacement_range"] = 0.1
    if integrator:
        flags += ["--integrator", integrator]
        arguments["integrator"] = integrator
    cli_trace, cli_stats = cli_simulate(cli, hard_csv, tmp_path, *flags)
    trace, stats = stickslip.simulate(str(hard_csv), **arguments)
    assert_same_run(trace, stats, cli_trace, cli_stats)
    assert stats["end_stop_contacts"] > 10


def test_arguments_override_the_scene_as_the_flags_do(cli, lorry_csv, tmp_path, source_dir):
    path = source_dir / "docs" / "scenes" / "lorry-seat-stick-slip.toml"
    cli_trace, cli_stats = cli_simulate(cli, lorry_csv, tmp_path, "--scene", path, "--ffk", 20,
                                        "--damping", 300)
    trace, stats = stickslip.simulate(str(lorry_csv), scene=path, ffk=20, damping=300)
    assert_same_run(trace, stats, cli_trace, cli_stats)


def test_no_trace_gives_the_same_statistics(lorry_csv):
    trace, stats = stickslip.simulate(str(lorry_csv), ffk=45)
    none, alone = stickslip.simulate(str(lorry_csv), ffk=45, trace=False)
    assert none is None
    assert {k: v for k, v in alone.items() if k != "ns_per_sample"} == \
        {k: v for k, v in stats.items() if k != "ns_per_sample"}


def test_non_contiguous_and_integer_input_is_converted(lorry_csv):
    recording = stickslip.read_recording(lorry_csv)
    doubled = np.repeat(recording["a_u"], 2)[::2]  # a strided view of the same samples
    assert not doubled.flags["C_CONTIGUOUS"]
    a, _ = stickslip.simulate(recording["a_u"], recording["dt"], ffk=45)
    b, _ = stickslip.simulate(doubled, recording["dt"], ffk=45)
    assert np.array_equal(a["a_x"], b["a_x"])
    c, _ = stickslip.simulate([0, 1, 0, -1, 0], 0.001, ffk=45)
    assert c["a_u"].dtype == np.float64 and list(c["a_u"]) == [0.0, 1.0, 0.0, -1.0, 0.0]
