"""Oscillator and Observer, stepped sample by sample, give simulate's trace bit for bit."""

import numpy as np
import pytest

import stickslip

CASES = [dict(model="stick-slip", ffk=45), dict(model="stick-slip", ffk=45, scalar="float"),
         dict(model="signum", ffk=45, integrator="euler"),
         dict(model="smooth", ffk=45, smoothing="tanh"),
         dict(model="stribeck", ffk=40, ffs=60), dict(model="linear", damping=0)]


@pytest.fixture(scope="module")
def recording(lorry_csv):
    rec = stickslip.read_recording(lorry_csv)
    n = 4000  # 4 s: sticking, break-away and reversals
    return rec["a_u"][:n], rec["dt"]


@pytest.mark.parametrize("params", CASES, ids=[str(p) for p in CASES])
def test_stepping_equals_simulate(recording, params):
    a_u, dt = recording
    trace, _ = stickslip.simulate(a_u, dt, **params)
    seat = stickslip.Oscillator(dt, **params)
    seat.reset(0.0, 0.0, a_u[0])
    rows = [seat.current()] + [seat.step(a) for a in a_u[1:]]
    for name, attribute in (("x_r", "x_r"), ("v_r", "v_r"), ("a_x", "a_x"), ("f_f", "f_f"),
                            ("stuck", "stuck")):
        stepped = np.array([getattr(row, attribute) for row in rows])
        assert np.array_equal(stepped, trace[name]), name


@pytest.mark.parametrize("params", CASES[:2], ids=[str(p) for p in CASES[:2]])
def test_run_over_an_array_equals_stepping(recording, params):
    a_u, dt = recording
    trace, _ = stickslip.simulate(a_u, dt, **params)
    seat = stickslip.Oscillator(dt, **params)
    seat.reset(0.0, 0.0, a_u[0])
    head = [seat.step(a) for a in a_u[1:100]]
    rest = seat.run(a_u[100:])
    assert np.array_equal(np.array([r.a_x for r in head]), trace["a_x"][1:100])
    for name in ("x_r", "v_r", "a_x", "f_f", "stuck"):
        assert np.array_equal(rest[name], trace[name][100:]), name


def test_scene_with_end_stops_steps_its_own_model(recording, source_dir):
    a_u, dt = recording
    scene = source_dir / "docs" / "scenes" / "seat-with-end-stops.toml"
    trace, _ = stickslip.simulate(a_u * 20, dt, scene=scene)
    seat = stickslip.Oscillator(dt, scene=scene)
    seat.reset(0.0, 0.0, a_u[0] * 20)
    rest = seat.run(a_u[1:] * 20)
    assert np.array_equal(rest["x_r"], trace["x_r"][1:])


def test_oscillator_refuses_what_simulate_would_refuse():
    with pytest.raises(ValueError, match=r"^mass: mass_kg: "):
        stickslip.Oscillator(0.001, mass=0)
    with pytest.raises(ValueError, match=r"use simulate\(\) for fixed point"):
        stickslip.Oscillator(0.001, scalar="fixed")


def test_observer_model_follows_the_oscillator_and_judges_the_regime(recording):
    a_u, dt = recording
    seat = stickslip.Oscillator(dt, model="stick-slip", ffk=45)
    observer = stickslip.Observer(dt, window_s=1.0, model="stick-slip", ffk=45)
    seat.reset(0.0, 0.0, a_u[0])
    observer.reset(a_u[0])
    for a in a_u[1:]:
        expected = seat.step(a)
        estimate = observer.update(a, expected.a_x)
        assert estimate.model.a_x == expected.a_x
        assert estimate.measured and estimate.residual == 0.0
    summary = observer.summary()
    assert summary["samples"] == len(a_u) - 1
    assert summary["window_full"]
    assert summary["regime"] == "stick-slip required"  # K ~ 1.3 on this recording
    assert not summary["model_mismatch"]


def test_observer_of_the_end_stop_scene_follows_its_oscillator(hard_csv, source_dir):
    recording = stickslip.read_recording(hard_csv)
    a_u, dt = recording["a_u"], recording["dt"]
    scene = source_dir / "docs" / "scenes" / "seat-with-end-stops.toml"
    trace, stats = stickslip.simulate(a_u, dt, scene=scene)
    assert stats["end_stop_contacts"] > 10
    observer = stickslip.Observer(dt, window_s=1.0, scene=scene)
    observer.reset(a_u[0])
    estimates = [observer.update(a, measured) for a, measured in zip(a_u[1:], trace["a_x"][1:])]
    assert np.array_equal(np.array([e.model.x_r for e in estimates]), trace["x_r"][1:])
    assert np.array_equal(np.array([e.model.a_x for e in estimates]), trace["a_x"][1:])
    assert all(e.measured and e.residual == 0.0 for e in estimates)
    assert observer.summary()["samples"] == len(a_u) - 1


def test_observer_refuses_a_window_shorter_than_its_blocks():
    with pytest.raises(ValueError, match=r"^window_s: window_s = "):
        stickslip.Observer(0.001, window_s=0.001)
