"""Fixtures: the real `stickslip` command (STICKSLIP_CLI, set by CTest) and recordings it wrote."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

COLUMNS = ("t", "a_u", "x_r", "v_r", "a_x", "f_f", "stuck")


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("STICKSLIP_CLI")
    if not path:
        pytest.skip("STICKSLIP_CLI (the stickslip executable) is not set; run through CTest")
    return path


@pytest.fixture(scope="session")
def source_dir():
    return Path(os.environ.get("STICKSLIP_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def run_cli(cli, *args):
    """Runs the command; returns its stdout (raises with its stderr on failure)."""
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(done.stderr.strip())
    return done.stdout


def cli_error(cli, *args):
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    assert done.returncode != 0
    return done.stderr.strip()


def generated_lorry(cli, tmp_path_factory, name, rms, duration, seed):
    """`stickslip generate --kind lorry` at dt = 1 ms into a fresh directory."""
    path = tmp_path_factory.mktemp("recordings") / name
    run_cli(cli, "generate", "--kind", "lorry", "--rms", rms, "--duration", duration, "--dt", 0.001,
            "--seed", seed, "--output", path)
    return path


@pytest.fixture(scope="session")
def lorry_csv(cli, tmp_path_factory):
    """20 s of the lorry recording at K ~ 1 for F_fk = 45 N: sticking, slipping and events."""
    return generated_lorry(cli, tmp_path_factory, "lorry.csv", 0.35, 20, 1)


@pytest.fixture(scope="session")
def hard_csv(cli, tmp_path_factory):
    """10 s of the lorry recording at RMS 4 m/s^2: the seat of the end-stop scene hits its stops."""
    return generated_lorry(cli, tmp_path_factory, "hard.csv", 4, 10, 2)


def cli_simulate(cli, input_path, out_dir, *flags):
    """`stickslip simulate` once (--repetitions 1): (columns as float64 arrays, stats dict)."""
    output = Path(out_dir) / "out.csv"
    stdout = run_cli(cli, "simulate", "--input", input_path, "--output", output,
                     "--repetitions", 1, *flags)
    stats = json.loads(stdout.strip().splitlines()[-1])
    table = np.loadtxt(output, delimiter=",", skiprows=1, dtype=np.float64)
    with open(output) as header:
        assert header.readline().strip() == ",".join(COLUMNS)
    return {name: table[:, i] for i, name in enumerate(COLUMNS)}, stats
