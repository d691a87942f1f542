"""stickslip: a seat suspension with dry friction, simulated sample by sample.

The C++ core and the host library of the ``stickslip`` command, for numpy arrays:

    rec = stickslip.generate("lorry", rms=0.35, duration=120, dt=1e-3, seed=1)
    trace, stats = stickslip.simulate(rec["a_u"], rec["dt"], model="stick-slip", ffk=45)
    stats["T_ax"], stats["p_stick"], trace["a_x"]

``simulate`` runs the command's own loop, so ``trace`` and ``stats`` equal what
``stickslip simulate`` writes for the same samples, bit for bit (``stats`` has the keys of its
JSON line). Bad arguments and bad files raise ValueError with the library's message.

Parameters (SI units) shared by simulate, simulate_batch, Oscillator and Observer; None means
"the default", which is the reference seat (or the scene file's value when ``scene`` is given,
the arguments overriding the file as the command's flags do):

    model               linear | signum | smooth | stick-slip (default) | stribeck
    mass                kg (88.4)
    stiffness           N/m (11500)
    damping             N s/m (504)
    ffk                 kinetic friction F_fk, N (0)
    ffs                 static friction F_fs, N (= ffk)
    stribeck_velocity   v_S, m/s (0.01; stribeck)
    smoothing           atan | tanh (default) | erf | rational (smooth)
    smoothing_c         c in s(c v_r), s/m (1000; smooth)
    integrator          euler | symplectic | rk4 | exact | reference (the model's default:
                        exact for linear, signum, stick-slip; rk4 for smooth, stribeck)
    scalar              double (default) | float | fixed (Q23.40) | fixed32 (Q7.24)
    input_range         fixed point: largest |a_u| its scaling must hold, m/s^2 (50)
    displacement_range  fixed point: largest |x_r| its scaling must hold, m (1)
    x0, v0              initial x_r (m) and v_r (m/s) (0)
    scene               a scene TOML file (docs/scenes/)
    repetitions         timed runs for stats["ns_per_sample"] (1)
"""

import json as _json
import os as _os

from . import _stickslip
from ._stickslip import Step, Estimate

__all__ = ["simulate", "simulate_batch", "read_recording", "resample", "generate",
           "den_hartog_factor",
           "Oscillator", "Observer", "Step", "Estimate"]

_PARAMETERS = ("model", "mass", "stiffness", "damping", "ffk", "ffs", "stribeck_velocity",
               "smoothing", "smoothing_c", "integrator", "scalar", "input_range",
               "displacement_range", "x0", "v0", "scene", "repetitions")


def _options(values):
    return {key: value for key, value in values.items() if value is not None}


def simulate(a_u, dt=None, model=None, mass=None, stiffness=None, damping=None, ffk=None,
             ffs=None, integrator=None, scalar="double", scene=None, *, stribeck_velocity=None,
             smoothing=None, smoothing_c=None, input_range=None, displacement_range=None,
             x0=None, v0=None, repetitions=None, trace=True, f_a=None):
    """Runs the seat model over a recording; returns (trace, stats).

    a_u: the cab-floor acceleration, m/s^2 (a 1-D array, or the path of a recording that
    `stickslip simulate --input` reads without further flags: CSV, .mat, a logger's text with a
    column a_u; its time column gives dt and its column f_a, when it has one, the actuator
    force). dt: the sample interval, s (arrays only). f_a: the actuator force on the seat, N,
    upward positive, one per sample of a_u and held over the step that ends at it (arrays only;
    None: no actuator).

    trace: dict of numpy arrays t, a_u, x_r, v_r, a_x, f_f (float64) and stuck (bool), one row
    per input sample, row 0 the initial state (None with trace=False). stats: dict with the keys
    and values of `stickslip simulate`'s JSON line (input: the path, or "" for an array; output:
    ""). See the module's docstring for the parameters.
    """
    options = _options(dict(model=model, mass=mass, stiffness=stiffness, damping=damping,
                            ffk=ffk, ffs=ffs, integrator=integrator, scalar=scalar, scene=scene,
                            stribeck_velocity=stribeck_velocity, smoothing=smoothing,
                            smoothing_c=smoothing_c, input_range=input_range,
                            displacement_range=displacement_range, x0=x0, v0=v0,
                            repetitions=repetitions))
    return _stickslip.simulate(a_u, dt, options, trace, f_a)


def simulate_batch(a_u, dt, params_list, threads=0, trace=True, f_a=None):
    """Runs every parameter set of params_list (dicts of simulate's keyword arguments) over one
    recording (and actuator force f_a, if given), on `threads` threads (0: all cores) with the
    GIL released.

    Returns a list of (trace, stats), in the order of params_list, each equal to
    simulate(a_u, dt, f_a=f_a, **params). The traces share their t and a_u arrays.
    """
    return _stickslip.simulate_batch(a_u, dt, [_options(dict(p)) for p in params_list],
                                     threads, trace, f_a)


def read_recording(path, dt=1e-3):
    """Reads a recording as `simulate` reads it (CSV with t,a_u and optionally f_a, MATLAB .mat
    with a_u plus t or dt, a logger's text with a column a_u), or a candump log (.log) of
    SeatInput frames (one sample per frame, t = n dt; frames of other ids or with a bad CRC are
    skipped and counted in "skipped_frames").

    Returns a dict with numpy arrays t, a_u, the sample interval dt (s) and, when the file has
    the column, f_a (N): simulate(r["a_u"], r["dt"], f_a=r.get("f_a")) runs what
    simulate(path) runs.
    """
    return _stickslip.read_recording(_os.fspath(path), dt)


def resample(a_u, dt, new_dt):
    """A uniform recording at sample interval dt put onto new_dt (s), as `stickslip simulate
    --dt` does (libsoxr, very high quality, its delay removed): the same samples. The span is
    kept; samples start at t = 0.

    Returns a dict with numpy arrays t = n new_dt, a_u (m/s^2) and dt = new_dt, so that
    ``simulate(r["a_u"], r["dt"], scene=...)`` runs a scene whose sample rate is not the
    recording's.
    """
    return _stickslip.resample(a_u, dt, new_dt)


def generate(kind, rms=None, duration=10.0, dt=1e-3, seed=1, *, frequency=0.0, band_low=0.5,
             band_high=20.0):
    """A synthetic cab-floor recording, the same samples `stickslip generate` writes.

    kind: wideband | lorry | harmonic (frequency, Hz) | white (band_low..band_high, Hz) | a
    seat-test spectrum EM1..EM9, IT1, IT4, AG2, AG3 (rms None: the standard's level).
    Returns a dict with numpy arrays t = n dt, a_u (m/s^2) and dt.
    """
    return _stickslip.generate(kind, rms, duration, dt, seed, frequency, band_low, band_high)


def den_hartog_factor(ffk, mass, rms_u):
    """Den Hartog's K = 4 F_fk / (pi sqrt(2) m a0u)."""
    return _stickslip.den_hartog_factor(ffk, mass, rms_u)


class Oscillator(_stickslip.Oscillator):
    """The core's oscillator, one sample at a time (scalar double or float).

        seat = stickslip.Oscillator(1e-3, model="stick-slip", ffk=45)
        seat.reset(x0=0, v0=0, a_u0=a_u[0])   # row 0: seat.current()
        out = seat.step(a_u[1])               # Step: x_r, v_r, a_x, f_f, stuck, events, ...
        rows = seat.run(a_u[2:])              # the same steps for an array (dict of arrays)

    With an actuator force (N, held over the step): reset(..., f_a0=f_a[0]),
    current(f_a=f_a[0]), step(a_u[n], f_a=f_a[n]), run(a_u, f_a=forces).

    reset() then step() over a recording gives simulate()'s trace bit for bit (with the same
    f_a, simulate(..., f_a=f_a)'s). Parameters as simulate's (x0, v0 set the state the
    constructor resets to, with a_u0 = 0).
    """

    def __init__(self, dt, **parameters):
        super().__init__(dt, _options(parameters))


class Observer(_stickslip.Observer):
    """The ECU's observer (double): update(a_u[, a_x_measured]) per sample gives an Estimate
    (the model's Step, the residual and friction estimate from a measured seat acceleration);
    summary() the window and exponential-window figures, K, the friction regime with
    hysteresis, and ride comfort. Parameters as simulate's, plus the observer's windows.
    """

    def __init__(self, dt, window_s=10.0, exponential_time_s=10.0, regime_hysteresis_k=0.05,
                 mismatch_rms=0.1, **parameters):
        super().__init__(dt, _options(parameters), window_s, exponential_time_s,
                         regime_hysteresis_k, mismatch_rms)
