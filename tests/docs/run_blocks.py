#!/usr/bin/env python3
"""Runs the command blocks of the project's docs and checks the figures they quote.

Docs: README.md, sim_host/README.md and docs/*.md (globbed when this runs, so a new page is
covered without a re-configure). Every fenced block whose info string is a shell (sh, bash,
shell, console) must carry a marker on the line(s) directly above its opening fence, written as
an HTML comment so that GitHub does not render it:

    <!-- docs-test: run -->                    run it (the default CTest test, label docs)
    <!-- docs-test: run label=vcan -->         run it only in the test of that label
    <!-- docs-test: skip reason="..." -->      never run it; the reason is printed
    <!-- docs-test: expect FILE "KEY": VALUE ±TOL -->
                                              after the block, the JSON in FILE (a path in the
                                              scratch directory, or "stdout": its last JSON line)
                                              has KEY within TOL of VALUE (the figure the doc
                                              quotes beside the block)
    <!-- docs-test: expect-files PATH... -->    after the block, these files exist
    <!-- docs-test: output -->                  (above a plain ``` block right after a run block)
                                              each non-empty line of that block appears in the
                                              block's stdout, whitespace runs compared as one
                                              space, "..." matching anything

An unmarked shell block fails the run, so that a new doc cannot escape the test.

Blocks of one page run in order in one scratch directory (a later block may use an earlier
block's files), under bash -e -o pipefail, with the build's stickslip first on PATH.

STICKSLIP_DOCS_SHORT=SECONDS (1 means 10 s) rewrites every `--duration S` longer than that to it,
for a quick local run; the numeric expectations and output blocks of a block it shortened are
then reported as not checked, because the quoted figures are those of the full-length input.
CTest runs the blocks at full length: together they take about 20 s.

Second mode, `json-keys`: runs `stickslip simulate` in several configurations and `stickslip
replay` on the loopback bus and compares the keys of their JSON lines with the key table of
sim_host/README.md (the table after `<!-- docs-test: json-keys -->`), and the keys `ecu` sets
(read from its JSON writer: ecu needs a CAN interface) with the table after
`<!-- docs-test: json-keys ecu -->`, and the keys of `stickslip closed-loop` (a single run and a
`--sweep-gain` run) with the table after `<!-- docs-test: json-keys closed-loop -->`. Third mode, `choices`:
the --integrator and --scalar choices of simulate, replay and ecu in sim_host/README.md's
synopsis against those each command's --help offers.
"""

import argparse
import glob
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys

SHELL_INFO = {"sh", "bash", "shell", "console", "zsh"}
MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})\s*([^`\s]*)")
SKIP_EXIT = 77  # CTest's SKIP_RETURN_CODE: every selected block needs what this machine lacks
BLOCK_TIMEOUT_S = 300


class DocError(Exception):
    pass


class Block:
    def __init__(self, path, line, info, code, markers):
        self.path = path          # relative to the source tree
        self.line = line          # 1-based line of the opening fence
        self.info = info
        self.code = code
        self.markers = markers    # list of (line, text)
        self.action = None        # "run" or "skip"
        self.label = ""
        self.reason = ""
        self.expects = []         # list of (line, text)
        self.output = None        # (line, [expected lines]) of a following output block

    def where(self):
        return f"{self.path}:{self.line}"


def doc_files(source):
    files = [os.path.join(source, "README.md"), os.path.join(source, "sim_host", "README.md")]
    files += sorted(glob.glob(os.path.join(source, "docs", "*.md")))
    return [f for f in files if os.path.isfile(f)]


def parse_marker_words(text):
    try:
        return shlex.split(text)
    except ValueError as error:
        raise DocError(f"cannot parse the marker '{text}': {error}")


def parse_doc(source, path):
    rel = os.path.relpath(path, source)
    with open(path, encoding="utf-8") as handle:
        lines = handle.read().split("\n")
    blocks, errors = [], []
    pending_output_for = None  # the run block an `output` marker refers to
    last_run = None
    n = 0
    while n < len(lines):
        fence = FENCE.match(lines[n])
        if not fence:
            n += 1
            continue
        indent, ticks, info = fence.group(1), fence.group(2), fence.group(3).lower()
        start = n
        body = []
        n += 1
        while n < len(lines):
            close = FENCE.match(lines[n])
            if close and close.group(2)[0] == ticks[0] and len(close.group(2)) >= len(ticks) \
                    and not close.group(3):
                break
            body.append(lines[n][len(indent):] if lines[n].startswith(indent) else lines[n])
            n += 1
        n += 1
        markers = []
        m = start - 1
        while m >= 0 and MARKER.match(lines[m]):
            markers.insert(0, (m + 1, MARKER.match(lines[m]).group(1)))
            m -= 1
        if info in SHELL_INFO:
            block = Block(rel, start + 1, info, "\n".join(body) + "\n", markers)
            try:
                classify(block)
            except DocError as error:
                errors.append((block.where(), str(error)))
                continue
            blocks.append(block)
            if block.action == "run":
                last_run = block
        elif any(text.split()[:1] == ["output"] for _, text in markers):
            if last_run is None:
                errors.append((f"{rel}:{start + 1}", "an output block with no run block before it"))
            else:
                last_run.output = (start + 1, [l for l in body if l.strip()])
        elif markers:
            errors.append((f"{rel}:{start + 1}", f"docs-test marker on a '{info or 'plain'}' "
                                                 f"block (only shell blocks run)"))
    return blocks, errors


def classify(block):
    for line, text in block.markers:
        words = parse_marker_words(text)
        if not words:
            raise DocError("empty docs-test marker")
        kind = words[0]
        if kind in ("run", "skip"):
            if block.action:
                raise DocError("marked both run and skip, or twice")
            block.action = kind
            for word in words[1:]:
                key, _, value = word.partition("=")
                if kind == "run" and key == "label" and value:
                    block.label = value
                elif kind == "skip" and key == "reason" and value:
                    block.reason = value
                else:
                    raise DocError(f"unknown {kind} option '{word}'")
            if kind == "skip" and not block.reason:
                raise DocError('a skipped block needs reason="..."')
        elif kind in ("expect", "expect-files"):
            block.expects.append((line, text))
        else:
            raise DocError(f"unknown docs-test marker '{kind}'")
    if not block.action:
        raise DocError(f"unmarked {block.info} block: put <!-- docs-test: run --> or "
                       f'<!-- docs-test: skip reason="..." --> on the line above its fence')
    if block.action == "skip" and block.expects:
        raise DocError("a skipped block cannot have expectations")


def short_seconds():
    value = os.environ.get("STICKSLIP_DOCS_SHORT", "")
    if not value or value == "0":
        return None
    seconds = float(value)
    return 10.0 if seconds == 1 else seconds


def shorten(code, seconds):
    def replace(match):
        return match.group(1) + (f"{seconds:g}" if float(match.group(2)) > seconds
                                 else match.group(2))
    return re.sub(r"(--duration[ =])([0-9.]+)", replace, code)


# --- expectations ------------------------------------------------------------------------------

EXPECT_VALUE = re.compile(r'^expect\s+(\S+)\s+"([^"]+)"\s*:\s*(\S+)\s*(?:±|\+-)\s*(\S+)\s*$')


def last_json_line(text):
    for line in reversed(text.splitlines()):
        line = line.strip()
        if line.startswith("{"):
            try:
                return json.loads(line)
            except ValueError:
                continue
    return None


def check_expect(text, stdout, cwd, shortened):
    """Returns None when it holds, else what did not match."""
    if text.startswith("expect-files"):
        missing = [p for p in text.split()[1:] if not os.path.exists(os.path.join(cwd, p))]
        return f"files not written: {' '.join(missing)}" if missing else None
    match = EXPECT_VALUE.match(text)
    if not match:
        return f"cannot parse '{text}' (expect FILE \"KEY\": VALUE ±TOL)"
    source, key, value, tolerance = match.groups()
    if shortened:
        return None  # the figure is the full-length input's: not comparable
    if source == "stdout":
        data = last_json_line(stdout)
        if data is None:
            return "no JSON line on stdout"
    else:
        try:
            with open(os.path.join(cwd, source), encoding="utf-8") as handle:
                data = json.load(handle)
        except (OSError, ValueError) as error:
            return f"{source}: {error}"
    node = data
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return f'{source}: no key "{key}"'
        node = node[part]
    if isinstance(value, str) and not re.match(r"^[-+0-9.eE]+$", value):
        return None if str(node) == value else f'{source} "{key}": {node!r}, the doc says {value}'
    if not isinstance(node, (int, float)) or isinstance(node, bool) \
            or not math.isfinite(node) or abs(node - float(value)) > float(tolerance):
        return f'{source} "{key}": {node}, the doc says {value} ±{tolerance}'
    return None


def output_pattern(expected_line):
    parts = [re.escape(" ".join(p.split())) for p in expected_line.split("...")]
    return re.compile(".*".join(parts))


def check_output(expected, stdout):
    actual = [" ".join(line.split()) for line in stdout.splitlines()]
    problems = []
    for line in expected:
        pattern = output_pattern(line.strip())
        if not any(pattern.search(a) for a in actual):
            problems.append(f"output line not found: {line.strip()}")
    return problems


# --- running -----------------------------------------------------------------------------------

def tail(text, lines=15):
    return "\n".join(text.rstrip("\n").splitlines()[-lines:])


def run_block(block, cwd, env, short, inputs_shortened):
    """inputs_shortened: an earlier block of the page made its files from a shortened input."""
    code = shorten(block.code, short) if short is not None else block.code
    try:
        result = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", code], cwd=cwd, env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                errors="replace", timeout=BLOCK_TIMEOUT_S)
        output, status = result.stdout, result.returncode
    except subprocess.TimeoutExpired as expired:
        output = expired.stdout or ""
        if isinstance(output, bytes):
            output = output.decode(errors="replace")
        return [f"timed out after {BLOCK_TIMEOUT_S} s"], code, output
    problems = []
    shortened = inputs_shortened or code != block.code
    if status != 0:
        problems.append(f"exit status {status}")
    else:
        for line, text in block.expects:
            problem = check_expect(text, output, cwd, shortened)
            if problem:
                problems.append(f"(marker at line {line}) {problem}")
        if block.output and not shortened:
            problems += [f"(output block at line {block.output[0]}) {p}"
                         for p in check_output(block.output[1], output)]
    return problems, code, output


def label_available(label):
    """None when this machine can run the label's blocks, else why not."""
    if label == "vcan":
        return None if os.path.exists("/sys/class/net/vcan0") else "no vcan0 interface here"
    if label == "slurm":
        if not shutil.which("sbatch") or not shutil.which("squeue"):
            return "no sbatch or squeue on PATH"
        probe = subprocess.run(["squeue", "--noheader"], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
        return None if probe.returncode == 0 else "no reachable Slurm controller"
    return f"no check for label '{label}' in the runner"


def git_status(source):
    try:
        result = subprocess.run(["git", "-C", source, "status", "--porcelain"],
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    except OSError:
        return None
    return result.stdout if result.returncode == 0 else None


def slug(rel):
    return re.sub(r"[^A-Za-z0-9]+", "-", rel).strip("-")


def run_docs(args):
    source = os.path.abspath(args.source)
    scratch = os.path.abspath(args.scratch)
    binary_dir = os.path.dirname(os.path.abspath(args.stickslip))
    env = dict(os.environ)
    env["PATH"] = binary_dir + os.pathsep + env.get("PATH", "")
    env.pop("STICKSLIP_DOCS_SHORT", None)  # the blocks themselves never see it
    short = short_seconds()

    before = git_status(source)
    blocks, errors = [], []
    for path in doc_files(source):
        found, problems = parse_doc(source, path)
        blocks += found
        errors += problems
    for where, error in errors:
        print(f"{where}: FAILED ({error})")

    unavailable = label_available(args.label) if args.label else None
    counts = {"found": len(blocks) + len(errors), "run": 0, "failed": len(errors)}
    skipped = {}

    def skip(block, reason):
        print(f"{block.where()}: SKIPPED ({reason})")
        skipped[reason] = skipped.get(reason, 0) + 1

    by_file = {}
    for block in blocks:
        by_file.setdefault(block.path, []).append(block)
    for rel, file_blocks in by_file.items():
        wanted = [b for b in file_blocks if b.action == "run" and b.label == args.label]
        cwd = os.path.join(scratch, slug(rel) + (f"-{args.label}" if args.label else ""))
        if wanted and not unavailable:
            shutil.rmtree(cwd, ignore_errors=True)
            os.makedirs(cwd)
        last_wanted = wanted[-1] if wanted else None
        page_shortened = False
        for block in file_blocks:
            if block.action == "skip":
                skip(block, block.reason)
                continue
            if block.label != args.label:
                # A labelled run still needs the page's unlabelled blocks before it (its inputs).
                needed = args.label and not block.label and last_wanted is not None \
                    and block.line < last_wanted.line and not unavailable
                if not needed:
                    skip(block, f"label {block.label}: runs in the test docs.{block.label}"
                         if block.label
                         else "not this label's block")
                    continue
            elif unavailable:
                skip(block, f"label {args.label}: {unavailable}")
                continue
            problems, code, output = run_block(block, cwd, env, short, page_shortened)
            page_shortened = page_shortened or code != block.code
            unchecked = page_shortened and (block.output or any(
                text.startswith("expect ") for _, text in block.expects))
            counts["run"] += 1
            if problems:
                counts["failed"] += 1
                print(f"{block.where()}: FAILED")
                print("  command:\n" + "\n".join("    " + l for l in code.rstrip().splitlines()))
                print("  output (tail):\n" +
                      "\n".join("    " + l for l in tail(output).splitlines()))
                for problem in problems:
                    print(f"  did not match: {problem}")
            else:
                note = " (figures not checked: shortened by STICKSLIP_DOCS_SHORT)" if unchecked \
                    else ""
                print(f"{block.where()}: ok{note}")

    after = git_status(source)
    if before is None:
        print("note: the source tree is not a git checkout; not checked for writes")
    elif after != before:
        counts["failed"] += 1
        print("FAILED: the blocks changed the source checkout (git status --porcelain):")
        old, new = set(before.splitlines()), set(after.splitlines())
        for line in sorted(new ^ old):
            print(f"  {line}")

    print(f"\nblocks found: {counts['found']}, run: {counts['run']}, "
          f"failed: {counts['failed']}, skipped: {sum(skipped.values())}")
    for reason, count in sorted(skipped.items(), key=lambda item: -item[1]):
        print(f"  skipped {count}: {reason}")
    if counts["failed"]:
        return 1
    if args.label and unavailable:
        return SKIP_EXIT
    if args.label and counts["run"] == 0:
        print(f"no block has label {args.label}")
        return 1
    return 0


# --- json-keys -----------------------------------------------------------------------------------

def documented_keys(source, table=()):
    """Rows of the table after `<!-- docs-test: json-keys [TABLE] -->`: {key: condition}."""
    path = os.path.join(source, "sim_host", "README.md")
    with open(path, encoding="utf-8") as handle:
        lines = handle.read().split("\n")
    for n, line in enumerate(lines):
        marker = MARKER.match(line)
        if marker and marker.group(1).split() == ["json-keys", *table]:
            break
    else:
        raise DocError(f"{path}: no <!-- docs-test: {' '.join(['json-keys', *table])} --> table")
    keys = {}
    for line in lines[n + 1:]:
        if not line.strip():
            if keys:
                break
            continue
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        names = re.findall(r"`([^`]+)`", cells[0])
        for name in names:
            keys[name] = cells[1] if len(cells) > 1 else ""
    if not keys:
        raise DocError(f"{path}:{n + 1}: the json-keys table is empty")
    return keys


def flatten(data):
    keys = set()
    for key, value in data.items():
        if isinstance(value, dict) and key != "faults":
            keys |= {f"{key}.{inner}" for inner in value}
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            keys |= {f"{key}[].{inner}" for v in value for inner in v}
        else:
            keys.add(key)
    return keys


def run_json_keys(args):
    stickslip = os.path.abspath(args.stickslip)
    scratch = os.path.abspath(args.scratch)
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    documented = documented_keys(os.path.abspath(args.source))

    def run(*command):
        result = subprocess.run([stickslip, *command], cwd=scratch, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, timeout=BLOCK_TIMEOUT_S)
        if result.returncode != 0:
            raise DocError(f"stickslip {' '.join(command)}: exit {result.returncode}\n"
                           f"{tail(result.stdout)}")
        return result.stdout

    run("generate", "--kind", "lorry", "--rms", "0.35", "--duration", "2", "--dt", "0.001",
        "--output", "in.csv")
    # The same samples with 0.1 s lost, as a logger drops data: read with recording options, the
    # statistics gain what reading did (`recording`) and, split at the gap, each part's figures.
    with open(os.path.join(scratch, "in.csv")) as source:
        rows = source.read().splitlines()
    with open(os.path.join(scratch, "gapped.csv"), "w") as gapped:
        gapped.write("\n".join(rows[:801] + rows[901:]) + "\n")
    base = ["--input", "in.csv", "--output", "out.csv", "--repetitions", "1", "--ffk", "45"]
    # A scene with end stops (as docs/scenes/seat-with-end-stops.toml), written here so that the
    # runner needs nothing of the source tree but its README.
    end_stops = os.path.join(scratch, "stops.toml")
    with open(end_stops, "w") as scene:
        scene.write('[scene]\neffects = ["spring", "damper", "coulomb", "static_friction", '
                    '"end_stops"]\n[seat]\nkinetic_friction_n = 30\nstatic_friction_n = 30\n'
                    '[end_stops]\ntravel_m = 0.05\nstiffness_n_per_m = 200000\n'
                    'damping_ns_per_m = 2000\n')
    runs = {
        "simulate stick-slip": ["simulate", *base, "--model", "stick-slip"],
        "simulate stribeck": ["simulate", *base, "--model", "stribeck", "--ffs", "60"],
        "simulate smooth": ["simulate", *base, "--model", "smooth"],
        "simulate --scalar fixed": ["simulate", *base, "--model", "stick-slip", "--scalar",
                                    "fixed"],
        "simulate --scalar fixed32": ["simulate", *base, "--model", "stick-slip", "--scalar",
                                      "fixed32", "--input-range", "32.768",
                                      "--displacement-range", "0.1"],
        "simulate --integrator reference": ["simulate", *base, "--model", "stick-slip",
                                            "--integrator", "reference"],
        "simulate --gaps split": ["simulate", "--input", "gapped.csv", "--output", "out.csv",
                                  "--repetitions", "1", "--ffk", "45", "--model", "stick-slip",
                                  "--gaps", "split"],
        "replay": ["replay", "--input", "in.csv", "--output", "out.csv", "--model",
                   "stick-slip", "--ffk", "45"],
        "simulate --scene end stops": ["simulate", "--input", "in.csv", "--output", "out.csv",
                                       "--repetitions", "1", "--scene", end_stops],
        "replay --scene end stops": ["replay", "--input", "in.csv", "--output", "out.csv",
                                     "--scene", end_stops],
    }
    failures, seen = compare_printed_keys(run, runs, documented, "sim_host/README.md's table")
    failures += check_ecu_keys(os.path.abspath(args.source))
    for node in ("plant", "controller"):
        failures += check_writer_keys(os.path.abspath(args.source), node,
                                      os.path.join("sim_host", "src", "bus", "control_nodes.cpp"),
                                      f"{node}_json")
    failures += check_closed_loop_keys(os.path.abspath(args.source), run, end_stops)
    for failure in failures:
        print(f"FAILED: {failure}")
    print(f"documented keys: {len(documented)}, printed keys: {len(seen)}")
    return 1 if failures else 0


def check_closed_loop_keys(source, run, end_stops):
    """`closed-loop`'s JSON line (a single run, one on the scene with end stops and a gain sweep)
    against the table after `<!-- docs-test: json-keys closed-loop -->`."""
    documented = documented_keys(source, ("closed-loop",))
    base = ["closed-loop", "--input", "in.csv", "--model", "stick-slip", "--ffk", "45"]
    runs = {
        "closed-loop skyhook-semi": [*base, "--output", "loop.csv", "--controller",
                                     "skyhook-semi"],
        "closed-loop --scene end stops": ["closed-loop", "--input", "in.csv", "--output",
                                          "loop.csv", "--controller", "skyhook", "--scene",
                                          end_stops],
        "closed-loop --sweep-gain": [*base, "--output", "sweep.csv", "--controller", "skyhook",
                                     "--sweep-gain", "0:2000:3", "--plot", "pareto.png"],
    }
    failures, _ = compare_printed_keys(run, runs, documented,
                                       "sim_host/README.md's closed-loop table")
    return failures


def compare_printed_keys(run, runs, documented, table):
    """Runs each command of `runs` (name -> arguments) and compares the keys of its JSON line with
    `documented` (key -> 'always' or a condition): every 'always' key in every run, every printed
    key in the table, every key of the table printed by some run. Returns (failures, seen)."""
    seen = {}
    failures = []
    for name, command in runs.items():
        data = last_json_line(run(*command))
        if data is None:
            failures.append(f"{name}: no JSON line on stdout")
            continue
        keys = flatten(data)
        for key in keys:
            seen.setdefault(key, []).append(name)
        absent = sorted(k for k, when in documented.items() if when == "always" and k not in keys)
        if absent:
            failures.append(f"{name}: keys documented as 'always' are missing: {', '.join(absent)}")
        print(f"{name}: {len(keys)} keys")
    extra = sorted(set(seen) - set(documented))
    missing = sorted(set(documented) - set(seen))
    if extra:
        failures.append(f"keys printed but not in {table}: " +
                        ", ".join(f"{k} ({seen[k][0]})" for k in extra))
    if missing:
        failures.append(f"keys in {table} that no run printed: " + ", ".join(missing))
    return failures, seen


def check_ecu_keys(source):
    """`ecu` needs a CAN interface (the vcan guest runs it): its table is checked against the keys
    its JSON writer, ecu_json() in sim_host/src/bus/bus_commands.cpp, sets."""
    documented = documented_keys(source, ("ecu",))
    path = os.path.join(source, "sim_host", "src", "bus", "bus_commands.cpp")
    if not os.path.isfile(path):
        return [f"{path}: missing, so the ecu keys cannot be read"]
    with open(path, encoding="utf-8") as handle:
        code = handle.read()
    body = re.search(r"\nstd::string ecu_json\(.*?\n}\n", code, flags=re.S)
    if body is None:
        return [f"{path}: no ecu_json() to read the ecu keys from"]
    written = set(re.findall(r'json\["([A-Za-z0-9_.]+)"\]', body.group(0)))
    failures = []
    if written - set(documented):
        failures.append("ecu keys set by ecu_json() but not in sim_host/README.md's ecu table: " +
                        ", ".join(sorted(written - set(documented))))
    if set(documented) - written:
        failures.append("keys in sim_host/README.md's ecu table that ecu_json() never sets: " +
                        ", ".join(sorted(set(documented) - written)))
    print(f"ecu: {len(written)} keys in ecu_json(), {len(documented)} documented")
    return failures


def check_writer_keys(source, table, relative_path, function):
    """A command that needs a CAN interface (plant, controller): its table (after
    `<!-- docs-test: json-keys TABLE -->`) against the keys its JSON writer FUNCTION sets."""
    documented = documented_keys(source, (table,))
    path = os.path.join(source, relative_path)
    if not os.path.isfile(path):
        return [f"{path}: missing, so the {table} keys cannot be read"]
    with open(path, encoding="utf-8") as handle:
        code = handle.read()
    body = re.search(r"\nstd::string " + re.escape(function) + r"\(.*?\n}\n", code, flags=re.S)
    if body is None:
        return [f"{path}: no {function}() to read the {table} keys from"]
    written = set(re.findall(r'json\["([A-Za-z0-9_.]+)"\]', body.group(0)))
    failures = []
    if written - set(documented):
        failures.append(f"{table} keys set by {function}() but not in sim_host/README.md's {table} "
                        "table: " + ", ".join(sorted(written - set(documented))))
    if set(documented) - written:
        failures.append(f"keys in sim_host/README.md's {table} table that {function}() never "
                        "sets: " + ", ".join(sorted(set(documented) - written)))
    print(f"{table}: {len(written)} keys in {function}(), {len(documented)} documented")
    return failures


# --- choices -------------------------------------------------------------------------------------

def documented_choices(source):
    """{(command, option): set of choices} from the synopsis block under sim_host/README.md's
    "## Commands"; a command documented as "model options as replay" inherits replay's."""
    path = os.path.join(source, "sim_host", "README.md")
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    section = text.split("## Commands", 1)
    if len(section) < 2 or "```" not in section[1]:
        raise DocError(f"{path}: no synopsis block under '## Commands'")
    synopsis = section[1].split("```", 2)[1]
    commands = {}
    for chunk in re.split(r"^(?=stickslip )", synopsis, flags=re.M):
        name = chunk.split()[1] if chunk.startswith("stickslip ") else None
        if name:
            commands[name] = commands.get(name, "") + chunk
    choices = {}
    for name in ("simulate", "replay", "ecu"):
        chunk = commands.get(name, "")
        if name == "ecu" and "model options as replay" in chunk:
            chunk = commands.get("replay", "")
        for option in ("--integrator", "--scalar"):
            found = re.search(option + r"\s+([a-z0-9]+(?:\|[a-z0-9]+)+)", chunk)
            choices[(name, option)] = set(found.group(1).split("|")) if found else set()
    return choices


def help_choices(stickslip, command, option):
    result = subprocess.run([stickslip, command, "--help"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    found = re.search(r"^\s*" + option + r"\s+TEXT\S*\s+([a-z0-9 |]+)", result.stdout,
                      flags=re.M)
    return {c.strip() for c in found.group(1).split("|") if c.strip()} if found else set()


def run_choices(args):
    stickslip = os.path.abspath(args.stickslip)
    failures = []
    for (command, option), documented in documented_choices(os.path.abspath(args.source)).items():
        offered = help_choices(stickslip, command, option)
        if not offered:
            failures.append(f"stickslip {command} --help: no choices for {option}")
        elif documented != offered:
            failures.append(
                f"{command} {option}: sim_host/README.md lists {'|'.join(sorted(documented))}, "
                f"--help offers {'|'.join(sorted(offered))}")
        else:
            print(f"{command} {option}: {'|'.join(sorted(offered))}: ok")
    for failure in failures:
        print(f"FAILED: {failure}")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mode", choices=["blocks", "json-keys", "choices"])
    parser.add_argument("--source", required=True, help="the source tree")
    parser.add_argument("--stickslip", required=True, help="the built stickslip")
    parser.add_argument("--scratch", required=True, help="scratch directory (build tree)")
    parser.add_argument("--label", default="", help="run only the blocks of this label")
    args = parser.parse_args()
    try:
        modes = {"blocks": run_docs, "json-keys": run_json_keys, "choices": run_choices}
        return modes[args.mode](args)
    except DocError as error:
        print(f"FAILED: {error}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
