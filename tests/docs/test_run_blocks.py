#!/usr/bin/env python3
"""The docs runner can fail: each check of run_blocks.py meets a page that breaks it.

Usage: test_run_blocks.py STICKSLIP SCRATCH SOURCE. Builds small source trees (git
repositories) under SCRATCH and runs the runner on them.
"""

import os
import shutil
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
RUNNER = os.path.join(HERE, "run_blocks.py")
STICKSLIP, SCRATCH, SOURCE = (os.path.abspath(a) for a in sys.argv[1:4])


def make_tree(name, readme, sim_host_readme=None):
    root = os.path.join(SCRATCH, name)
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(os.path.join(root, "sim_host", "src", "bus"))
    os.makedirs(os.path.join(root, "docs"))
    # The ecu keys are read from its JSON writer.
    shutil.copy(os.path.join(SOURCE, "sim_host", "src", "bus", "bus_commands.cpp"),
                os.path.join(root, "sim_host", "src", "bus"))
    with open(os.path.join(root, "README.md"), "w", encoding="utf-8") as handle:
        handle.write(readme)
    if sim_host_readme is not None:
        with open(os.path.join(root, "sim_host", "README.md"), "w", encoding="utf-8") as handle:
            handle.write(sim_host_readme)
    subprocess.run(["git", "init", "-q", root], check=True)
    subprocess.run(["git", "-C", root, "add", "."], check=True)
    subprocess.run(["git", "-C", root, "-c", "user.name=t", "-c", "user.email=t@t", "commit",
                    "-qm", "tree"], check=True)
    return root


def run(mode, root, *extra):
    result = subprocess.run([sys.executable, RUNNER, mode, "--source", root, "--stickslip",
                             STICKSLIP, "--scratch", os.path.join(root + "-scratch"), *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return result.returncode, result.stdout


GENERATE = ("stickslip generate --kind lorry --rms 0.35 --duration 2 --dt 0.001 --output in.csv\n"
            "stickslip simulate --input in.csv --output out.csv --stats stats.json "
            "--model stick-slip --ffk 45 --repetitions 1\n")


class Runner(unittest.TestCase):
    def test_passes_a_marked_block_whose_figure_holds(self):
        root = make_tree("good", "<!-- docs-test: run -->\n"
                                 '<!-- docs-test: expect stats.json "samples": 2001 ±0 -->\n'
                                 "```sh\n" + GENERATE + "```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 0, output)
        self.assertIn("README.md:3: ok", output)

    def test_fails_on_an_unmarked_shell_block(self):
        root = make_tree("unmarked", "text\n\n```sh\nstickslip --help\n```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 1, output)
        self.assertIn("README.md:3: FAILED (unmarked sh block", output)

    def test_fails_on_a_figure_that_no_longer_matches(self):
        root = make_tree("figure", "<!-- docs-test: run -->\n"
                                   '<!-- docs-test: expect stats.json "samples": 2000 ±0 -->\n'
                                   "```sh\n" + GENERATE + "```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 1, output)
        self.assertIn('stats.json "samples": 2001, the doc says 2000', output)

    def test_fails_on_a_missing_output_line(self):
        root = make_tree("output", "<!-- docs-test: run -->\n```sh\necho 'T_ax 0.95'\n```\n\n"
                                   "<!-- docs-test: output -->\n```\nT_ax 0.96\n```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 1, output)
        self.assertIn("output line not found: T_ax 0.96", output)

    def test_fails_on_a_failing_command_and_shows_it(self):
        root = make_tree("command", "<!-- docs-test: run -->\n```sh\n"
                                    "stickslip simulate --input missing.csv --output o.csv "
                                    "--model linear\n```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 1, output)
        self.assertIn("exit status 1", output)
        self.assertIn("stickslip simulate --input missing.csv", output)
        self.assertIn("missing.csv", output.split("output (tail):")[1])

    def test_fails_when_a_block_writes_into_the_source_checkout(self):
        root = make_tree("writes", "")
        with open(os.path.join(root, "README.md"), "w", encoding="utf-8") as handle:
            handle.write(f"<!-- docs-test: run -->\n```sh\ntouch {root}/leaked.csv\n```\n")
        subprocess.run(["git", "-C", root, "-c", "user.name=t", "-c", "user.email=t@t", "commit",
                        "-qam", "leak"], check=True)
        status, output = run("blocks", root)
        self.assertEqual(status, 1, output)
        self.assertIn("changed the source checkout", output)
        self.assertIn("leaked.csv", output)

    def test_prints_the_reason_of_a_skipped_block(self):
        root = make_tree("skip", '<!-- docs-test: skip reason="needs vcan0" -->\n```sh\n'
                                 "stickslip ecu --bus vcan0\n```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 0, output)
        self.assertIn("README.md:2: SKIPPED (needs vcan0)", output)

    def test_a_label_without_its_machine_is_skipped_with_exit_77(self):
        root = make_tree("label", "<!-- docs-test: run label=slurm -->\n```sh\nsqueue\n```\n")
        status, output = run("blocks", root)
        self.assertEqual(status, 0, output)
        self.assertIn("SKIPPED (label slurm: runs in the test docs.slurm)", output)
        if not shutil.which("sbatch"):
            status, output = run("blocks", root, "--label", "slurm")
            self.assertEqual(status, 77, output)

    def test_json_keys_names_the_missing_and_the_extra_keys(self):
        with open(os.path.join(SOURCE, "sim_host", "README.md"), encoding="utf-8") as handle:
            text = handle.read()
        text = text.replace("| `vdv`, `mtvv`, `crest_factor` |", "| `vdv`, `mtvv` |")
        text = text.replace("| `send_failures` |", "| `send_failures`, `no_such_key` |")
        root = make_tree("keys", "", text)
        status, output = run("json-keys", root)
        self.assertEqual(status, 1, output)
        self.assertIn("not in sim_host/README.md's table: crest_factor", output)
        self.assertIn("that no run printed: no_such_key", output)

    def test_json_keys_name_an_ecu_key_the_table_lacks(self):
        with open(os.path.join(SOURCE, "sim_host", "README.md"), encoding="utf-8") as handle:
            text = handle.read()
        self.assertIn("| `left_after_stop` | frames queued after the stop", text)
        text = text.replace("| `left_after_stop` | frames queued after the stop",
                            "| `left_over` | frames queued after the stop")
        root = make_tree("ecu-keys", "", text)
        status, output = run("json-keys", root)
        self.assertEqual(status, 1, output)
        self.assertIn("ecu keys set by ecu_json() but not in sim_host/README.md's ecu table: "
                      "left_after_stop", output)
        self.assertIn("keys in sim_host/README.md's ecu table that ecu_json() never sets: "
                      "left_over", output)

    def test_choices_name_a_synopsis_that_lists_fewer_integrators_than_help(self):
        with open(os.path.join(SOURCE, "sim_host", "README.md"), encoding="utf-8") as handle:
            text = handle.read()
        self.assertIn("euler|symplectic|rk4|exact|reference", text)
        text = text.replace("euler|symplectic|rk4|exact|reference", "euler|symplectic|rk4|exact")
        root = make_tree("choices", "", text)
        status, output = run("choices", root)
        self.assertEqual(status, 1, output)
        self.assertIn("simulate --integrator: sim_host/README.md lists euler|exact|rk4|symplectic, "
                      "--help offers euler|exact|reference|rk4|symplectic", output)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
