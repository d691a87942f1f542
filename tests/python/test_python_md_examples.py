"""docs/PYTHON.md's Python examples run as written and print what the page quotes.

The docs runner (tests/docs) runs shell blocks with the command alone on PATH; the module's
examples need the module, so they are run here, where it is importable.
"""

import contextlib
import io
import os
import re

from conftest import cli_simulate

# input: the example names its file relatively, the command here by its absolute path.
NOT_COMPARED = {"ns_per_sample", "output", "input"}


def python_blocks(source_dir):
    text = (source_dir / "docs" / "PYTHON.md").read_text()
    return re.findall(r"^```python\n(.*?)^```$", text, flags=re.MULTILINE | re.DOTALL)


def run_block(code, directory):
    """Runs `code` in `directory` as a pasted script; returns its namespace and its stdout."""
    namespace = {"__name__": "__main__"}
    printed = io.StringIO()
    previous = os.getcwd()
    os.chdir(directory)
    try:
        with contextlib.redirect_stdout(printed):
            exec(compile(code, "docs/PYTHON.md", "exec"), namespace)
    finally:
        os.chdir(previous)
    return namespace, printed.getvalue()


def forced_example(source_dir):
    blocks = [code for code in python_blocks(source_dir) if "forced.csv" in code]
    assert len(blocks) == 1
    return blocks[0]


def test_actuator_force_example_gives_the_commands_run_and_its_quoted_figures(cli, source_dir,
                                                                              tmp_path):
    example = forced_example(source_dir)
    namespace, printed = run_block(example, tmp_path)
    stats = namespace["stats"]
    _, cli_stats = cli_simulate(cli, tmp_path / "forced.csv", tmp_path, "--model", "stick-slip",
                                "--ffk", 40, "--ffs", 55)
    for key in set(cli_stats) | set(stats):
        if key not in NOT_COMPARED:
            assert stats.get(key) == cli_stats.get(key), key
    quoted = re.search(r"print\(stats\[\"T_ax\"\]\)  # (\S+),", example).group(1)
    assert printed.strip() == quoted == repr(cli_stats["T_ax"])


def test_actuator_force_example_quotes_the_unforced_figure(cli, source_dir, tmp_path):
    text = (source_dir / "docs" / "PYTHON.md").read_text()
    quoted = re.search(r"Without the column the same floor gives T_ax = (\S+):", text).group(1)
    floor = tmp_path / "floor.csv"
    _, printed = run_block(forced_example(source_dir), tmp_path)
    # The example's file without its force column, through the command.
    with open(tmp_path / "forced.csv") as forced, open(floor, "w") as out:
        for line in forced:
            out.write(line.rsplit(",", 1)[0] + "\n")
    _, cli_stats = cli_simulate(cli, floor, tmp_path, "--model", "stick-slip", "--ffk", 40,
                                "--ffs", 55)
    assert repr(cli_stats["T_ax"]) == quoted
    assert printed.strip() != quoted
