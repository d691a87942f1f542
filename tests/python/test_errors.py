"""Bad arguments and bad files raise ValueError carrying the library's own message."""

import numpy as np
import pytest

import stickslip
from conftest import cli_error


def core_part(message):
    """The message after the option/argument name ("--mass: mass_kg: ..." -> "mass_kg: ...")."""
    return message.split(": ", 1)[1]


@pytest.mark.parametrize("argument,flag,value", [
    ("mass", "--mass", -1.0),
    ("stiffness", "--stiffness", 0.0),
    ("ffk", "--ffk", -5.0),
    ("damping", "--damping", float("nan")),
])
def test_invalid_parameter_names_the_argument_and_carries_the_cores_message(
        cli, lorry_csv, tmp_path, argument, flag, value):
    with pytest.raises(ValueError) as raised:
        stickslip.simulate(str(lorry_csv), model="stick-slip", **{argument: value})
    message = str(raised.value)
    assert message.startswith(argument + ": ")
    cli_message = cli_error(cli, "simulate", "--input", lorry_csv, "--output",
                            tmp_path / "o.csv", "--model", "stick-slip", flag, value)
    assert cli_message.startswith("stickslip: " + flag + ": ")
    assert core_part(message) == core_part(cli_message[len("stickslip: "):])


def test_static_below_kinetic_friction_is_refused():
    with pytest.raises(ValueError, match=r"^ffs: static_friction_n: "):
        stickslip.simulate(np.zeros(10), 0.001, ffk=45, ffs=10)


def test_unknown_model_integrator_and_scalar_are_named():
    with pytest.raises(ValueError, match=r"^model: unknown model 'coulomb'"):
        stickslip.simulate(np.zeros(10), 0.001, model="coulomb")
    with pytest.raises(ValueError, match=r"^integrator: unknown integrator 'rk45'"):
        stickslip.simulate(np.zeros(10), 0.001, integrator="rk45")
    with pytest.raises(ValueError, match=r"^scalar: unknown scalar 'half'"):
        stickslip.simulate(np.zeros(10), 0.001, scalar="half")


def test_fixed_point_refuses_the_models_it_does_not_offer():
    with pytest.raises(ValueError, match=r"model"):
        stickslip.simulate(np.zeros(10), 0.001, model="stribeck", ffk=40, ffs=60, scalar="fixed")


def test_q7_24_refuses_what_its_ranges_cannot_hold_with_the_commands_reason(cli, source_dir,
                                                                            lorry_csv, tmp_path):
    # The end-stop scene's 30 N of friction is below 2^-14 of the force range 1 m of stroke gives.
    scene = source_dir / "docs" / "scenes" / "seat-with-end-stops.toml"
    with pytest.raises(ValueError, match=r"^ffk: kinetic_friction_n: in scene units") as refused:
        stickslip.simulate(np.zeros(10), 0.001, scene=scene, scalar="fixed32")
    output = tmp_path / "refused.csv"
    message = cli_error(cli, "simulate", "--scene", scene, "--scalar", "fixed32", "--input",
                        lorry_csv, "--output", output)
    assert message.startswith("stickslip: --ffk: ")
    assert core_part(message[len("stickslip: "):]) == core_part(str(refused.value))
    assert not output.exists()


def test_unknown_keyword_in_a_batch_names_it_and_its_index():
    with pytest.raises(ValueError, match=r"^params_list\[1\]: unknown parameter 'masss'"):
        stickslip.simulate_batch(np.zeros(10), 0.001, [{"ffk": 1}, {"masss": 80}])


def test_refused_parameter_set_in_a_batch_names_its_index():
    with pytest.raises(ValueError, match=r"^params_list\[2\]: mass: mass_kg: "):
        stickslip.simulate_batch(np.zeros(10), 0.001, [{}, {"ffk": 3}, {"mass": 0}])


def test_array_needs_dt_and_a_file_gives_its_own(lorry_csv):
    with pytest.raises(ValueError, match=r"^dt: the sample interval"):
        stickslip.simulate(np.zeros(10))
    with pytest.raises(ValueError, match=r"^dt: must be a finite number > 0"):
        stickslip.simulate(np.zeros(10), -1.0)
    with pytest.raises(ValueError, match=r"^dt: a recording file gives its own dt"):
        stickslip.simulate(str(lorry_csv), 0.001)


def test_time_step_the_integrator_cannot_take_is_refused_as_dt():
    with pytest.raises(ValueError, match=r"^dt: dt_s: "):
        stickslip.simulate(np.zeros(10), 1.0, model="signum", ffk=45, integrator="euler")


def test_two_dimensional_input_and_too_few_samples_are_refused():
    with pytest.raises(ValueError, match=r"^a_u: expected a 1-D array of samples, got 2"):
        stickslip.simulate(np.zeros((3, 2)), 0.001)
    with pytest.raises(ValueError, match=r"at least 2 samples"):
        stickslip.simulate(np.zeros(1), 0.001)


def test_float_run_refuses_samples_beyond_float_range():
    with pytest.raises(ValueError, match=r"beyond the range of a float"):
        stickslip.simulate(np.array([0.0, 1e300]), 0.001, scalar="float")


def test_bad_recording_gives_the_readers_file_and_line(cli, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,a_u\n0,0\n0.001,abc\n")
    with pytest.raises(ValueError) as raised:
        stickslip.read_recording(bad)
    assert str(raised.value).startswith(f"{bad}:3: column 'a_u'")
    cli_message = cli_error(cli, "simulate", "--input", bad, "--output", tmp_path / "o.csv",
                            "--model", "linear")
    assert cli_message == "stickslip: " + str(raised.value)
    with pytest.raises(ValueError, match=r"cannot"):
        stickslip.simulate(str(tmp_path / "missing.csv"))


def test_scene_with_a_different_sample_rate_is_refused(source_dir):
    scene = source_dir / "docs" / "scenes" / "lorry-seat-stick-slip.toml"
    with pytest.raises(ValueError, match=r"but the scene .* has sample_rate_hz"):
        stickslip.simulate(np.zeros(10), 0.002, scene=scene)


def test_non_finite_sample_in_an_array_is_refused_by_its_index_as_the_command_refuses_a_file(
        cli, tmp_path):
    bad = tmp_path / "nan.csv"
    bad.write_text("t,a_u\n0,0\n0.001,0.5\n0.002,nan\n0.003,0\n")
    cli_message = cli_error(cli, "simulate", "--input", bad, "--output", tmp_path / "o.csv",
                            "--model", "stick-slip", "--ffk", 40)
    assert cli_message == f"stickslip: {bad}:4: column 'a_u': 'nan' is not a finite number"
    with pytest.raises(ValueError, match=r"^a_u = nan at sample 2: simulate needs finite samples"):
        stickslip.simulate(np.array([0.0, 0.5, np.nan, 0.0]), 0.001, model="stick-slip", ffk=40)
    with pytest.raises(ValueError, match=r"^a_u = -inf at sample 1: "):
        stickslip.simulate_batch(np.array([0.0, -np.inf]), 0.001, [{}])
    with pytest.raises(ValueError, match=r"is not a finite number"):
        stickslip.simulate(str(bad))


@pytest.mark.parametrize("arguments,message", [
    (dict(kind="lorry", rms=-1.0), r"^rms: must be a finite number > 0, got -1"),
    (dict(kind="lorry", rms=1.0, dt=0.0), r"^dt: must be a finite number > 0, got 0"),
    (dict(kind="lorry", rms=1.0, duration=float("nan")), r"^duration: must be a finite number"),
    (dict(kind="lorry", rms=1.0, duration=1e-6), r"^duration/dt: 1e-06 s is shorter than one"),
    (dict(kind="harmonic", rms=1.0, frequency=1e6), r"^frequency: harmonic needs 0 < frequency"),
    (dict(kind="lorry", rms=1.0, dt=0.1), r"^dt: lorry needs 0.5/dt above 20 Hz"),
    (dict(kind="EM6", duration=-1.0), r"^duration: must be a finite number > 0, got -1"),
    (dict(kind="EM6", dt=0.5), r"^dt: EM6 has a corner at"),
])
def test_generate_errors_name_the_python_arguments_not_the_commands_flags(arguments, message):
    with pytest.raises(ValueError, match=message) as raised:
        stickslip.generate(**arguments)
    assert "--" not in str(raised.value)
