#!/usr/bin/env python3
"""An upper bound on the instructions one call of a function executes, read from an ARM ELF.

    tools/elf-wcet.py ELF ROOT --bounds FILE --target NAME [--set NAME=VALUE ...] [--list-loops]

Disassembles ELF with arm-none-eabi-objdump, splits every function reachable from ROOT into basic
blocks and finds its loops (natural loops of the control-flow graph: the blocks that reach a back
edge to a block dominating its source). Each loop needs a bound from the bounds file: a loop
without one, control flow the analysis cannot follow (an indirect branch or call, a jump table, a
loop entered other than at its header), a library routine called with a length its loop bounds do
not cover, or a bound that matches no loop of an analysed function is an error, never a guess.
The bound is then the longest path through each function, counting one per instruction (what
QEMU's -icount counts), with each loop charged its bound times its longest turn plus its longest
way out, and each call its callee's bound. Every path is taken as feasible and every loop as
running to its bound, so no execution exceeds the figure: a measured count above it means the
analysis or a loop bound is wrong.

Bounds file (JSON):
  "constants": {NAME: "source file"}: NAME's value is read from the file's `NAME = integer;`.
  "targets": {TARGET: {"loops": [...], "arguments": {...}}}, one per ELF build, where a loop is
    {"function": REGEX matched against the symbol from its start, "header": the loop's ordinal
     among the function's loop headers in address order, "bound": an integer or an expression of
     integers and constants (+ - * // ** and parentheses): the most times the loop's body runs
     per entry (its back edge is taken fewer times), "per_call": true when the bound holds for
     all entries in one call of the function together and counts every run of the body, one
     that leaves it from inside included (each run is then charged the longer of a turn and a
     way out through the body, once per call, and each entry the header's test alone),
     "shared": NAME, for per-call loops of one function whose runs together stay within the one
     bound they all state (the passes of one loop that the compiler split in two: charged the
     bound times the longest turn among them, once per call), "why": the reason}
  "calls": [{"function": REGEX, "callee": REGEX, "bound": as a loop's, "why": the reason}]: the
    function's own call sites of the callee together call it at most `bound` times per call of
    the function (wherever they sit, in loops or not): each site is charged nothing and the
    function bound times the callee's bound, once per call (a call-count fact, for a call that
    only some passes of a loop make);
  and "arguments": {ROUTINE: {"register": "r2", "at_most": N}}: every reachable call of ROUTINE
    must set that register to a constant <= N in the calling block (the lengths the routine's
    loop bounds assume).
--set NAME=VALUE takes a constant as VALUE (e.g. max_gap=0 for a frame that follows no gap).

Prints JSON: the bound, each function's bound and every loop with its bound and longest turn.
--list-loops prints the loops found (each bound taken as 1) before a table exists for them.
"""
import argparse
import ast
import importlib.util
import json
import os
import re
import subprocess
import sys

kFallsOff = -1  # the successor of a function's last instruction

CONDITIONS = ("eq", "ne", "cs", "cc", "hs", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt",
              "gt", "le")


def fail(message):
    sys.stderr.write(f"elf-wcet: {message}\n")
    raise SystemExit(1)


def base_mnemonic(mnemonic):
    """The mnemonic without its width suffix (.n/.w) and condition: 'bne.n' -> ('b', 'ne')."""
    m = mnemonic.split(".")[0]
    for cond in CONDITIONS:
        if m.endswith(cond) and len(m) > len(cond):
            stem = m[: -len(cond)]
            if stem in ("b", "bx", "bl", "blx", "pop", "ldm", "ldmia", "mov", "ldr"):
                return stem, cond
    return m, None


def read_elf(elf):
    # The function symbols as the call-graph tool reads them (name and size by start address).
    spec = importlib.util.spec_from_file_location(
        "elf_callgraph", os.path.join(os.path.dirname(os.path.abspath(__file__)), "elf-callgraph.py"))
    callgraph = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(callgraph)
    functions = callgraph.read_functions(elf)
    for f in functions.values():
        f["instructions"] = []
    dump = subprocess.run(["arm-none-eabi-objdump", "-d", "--no-show-raw-insn", elf], check=True,
                          capture_output=True, text=True).stdout
    header = re.compile(r"^([0-9a-f]+) <(.+)>:$")
    instruction = re.compile(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$")
    current, start = None, 0
    for line in dump.splitlines():
        m = header.match(line)
        if m:
            start = int(m.group(1), 16)
            current = functions.get(start)
            continue
        m = instruction.match(line)
        if not m or current is None:
            continue
        address = int(m.group(1), 16)
        if address >= start + current["size"]:
            continue
        operands = m.group(3).split(";")[0].strip()
        current["instructions"].append((address, m.group(2), operands))
    return functions


class Function:
    """One function's basic blocks, edges and calls."""

    def __init__(self, start, info, functions):
        self.start, self.name = start, info["name"]
        code = [i for i in info["instructions"] if not i[1].startswith(".")]
        self.code = code
        if not code:
            fail(f"{self.name}: no instructions")
        by_address = {a: k for k, (a, _, _) in enumerate(code)}
        end = start + info["size"]
        self.leaders = {code[0][0]}
        self.calls = set()
        # Per instruction: (successor addresses, is_exit, callee, tail_callee).
        flow = []
        for k, (address, mnemonic, operands) in enumerate(code):
            following = code[k + 1][0] if k + 1 < len(code) else None
            stem, cond = base_mnemonic(mnemonic)
            target = re.match(r"([0-9a-f]+) <", operands)
            target = int(target.group(1), 16) if target else None
            successors, exits, callee, tail = [following], False, None, None
            if stem in ("b", "cbz", "cbnz"):
                if stem in ("cbz", "cbnz"):
                    target = int(re.search(r"([0-9a-f]+) <", operands).group(1), 16)
                if target is None:
                    fail(f"{self.name}+{address - start:#x}: branch without a target: {mnemonic}")
                inside = start <= target < end
                conditional = cond is not None or stem != "b"
                if inside:
                    if target not in by_address:
                        fail(f"{self.name}+{address - start:#x}: branch into an instruction")
                    successors = [target] + ([following] if conditional else [])
                else:
                    if target not in functions:
                        fail(f"{self.name}+{address - start:#x}: branch out of the function")
                    tail = target
                    successors, exits = ([following] if conditional else []), True
                if inside:
                    self.leaders.add(target)
                if following is not None:
                    self.leaders.add(following)
            elif stem in ("bl", "blx"):
                if target is None:
                    fail(f"{self.name}+{address - start:#x}: indirect call ({mnemonic} {operands})")
                if target not in functions:
                    fail(f"{self.name}+{address - start:#x}: call to {target:#x}, not a function")
                if functions[target]["name"].startswith("__gnu_thumb1_case"):
                    fail(f"{self.name}+{address - start:#x}: jump table "
                         f"({functions[target]['name']})")
                callee = target
            elif stem == "bx" or (stem in ("pop", "ldm", "ldmia") and "pc" in operands) or (
                    stem in ("mov", "ldr") and operands.startswith("pc")):
                if stem == "bx" and operands != "lr":
                    fail(f"{self.name}+{address - start:#x}: indirect branch ({mnemonic} {operands})")
                if stem in ("mov", "ldr") and operands != "pc, [sp], #4":
                    fail(f"{self.name}+{address - start:#x}: indirect branch ({mnemonic} {operands})")
                exits = True
                successors = [following] if cond is not None else []
                if following is not None:
                    self.leaders.add(following)
            elif stem in ("tbb", "tbh"):
                fail(f"{self.name}+{address - start:#x}: jump table ({mnemonic})")
            elif re.search(r"\bpc\b", operands.split(",")[0]) and stem not in ("cmp", "tst"):
                fail(f"{self.name}+{address - start:#x}: write to pc ({mnemonic} {operands})")
            if successors and successors[-1] is None:
                # Padding after the last return is never reached; reaching this is an error.
                successors = successors[:-1] + [kFallsOff]
            flow.append((successors, exits, callee, tail))
        # Basic blocks: a leader up to the next leader or a control transfer.
        # leader -> cost (instructions), calls, tail calls, call sites, successors, exits, first
        self.blocks = {}
        block = None
        for k, (address, _, _) in enumerate(code):
            if address in self.leaders or block is None:
                block = {"cost": 0, "calls": [], "tails": [], "successors": [], "exits": False,
                         "first": address, "call_sites": []}
                self.blocks[address] = block
            successors, exits, callee, tail = flow[k]
            block["cost"] += 1
            if callee is not None or tail is not None:
                block["call_sites"].append((address, callee if callee is not None else tail))
            if callee is not None:
                block["calls"].append(callee)
                self.calls.add(callee)
            if tail is not None:
                block["tails"].append(tail)
                self.calls.add(tail)
            following = code[k + 1][0] if k + 1 < len(code) else None
            ends = (exits or tail is not None or successors != [following]
                    or following in self.leaders)
            if ends:
                block["successors"] = sorted(set(successors))
                block["exits"] = exits
                block = None
        self.entry = code[0][0]
        # Unreachable blocks (literal pools skipped above; code after a no-return call) go.
        seen, stack = set(), [self.entry]
        while stack:
            b = stack.pop()
            if b in seen:
                continue
            if b == kFallsOff:
                fail(f"{self.name}: control falls off the function's end")
            seen.add(b)
            stack.extend(self.blocks[b]["successors"])
        self.blocks = {b: v for b, v in self.blocks.items() if b in seen}
        self.calls = set()
        for b in self.blocks.values():
            self.calls.update(b["calls"])
            self.calls.update(b["tails"])

    def dominators(self):
        order, seen = [], set()

        def visit(b):
            stack = [(b, iter(self.blocks[b]["successors"]))]
            seen.add(b)
            while stack:
                node, it = stack[-1]
                advanced = False
                for s in it:
                    if s not in seen:
                        seen.add(s)
                        stack.append((s, iter(self.blocks[s]["successors"])))
                        advanced = True
                        break
                if not advanced:
                    order.append(node)
                    stack.pop()

        visit(self.entry)
        order.reverse()
        predecessors = {b: [] for b in self.blocks}
        for b, v in self.blocks.items():
            for s in v["successors"]:
                predecessors[s].append(b)
        dom = {b: set(self.blocks) for b in self.blocks}
        dom[self.entry] = {self.entry}
        changed = True
        while changed:
            changed = False
            for b in order[1:]:
                new = set.intersection(*(dom[p] for p in predecessors[b])) | {b}
                if new != dom[b]:
                    dom[b], changed = new, True
        return dom, predecessors

    def loops(self):
        """{header: body} of the natural loops; back edges to one header share a loop."""
        dom, predecessors = self.dominators()
        loops = {}
        for b, v in self.blocks.items():
            for s in v["successors"]:
                if s in dom[b]:
                    body = loops.setdefault(s, {s})
                    stack = [b]
                    while stack:
                        n = stack.pop()
                        if n not in body:
                            body.add(n)
                            stack.extend(predecessors[n])
        # Reducible: every edge into a loop from outside it enters at the header.
        for header, body in loops.items():
            for n in body - {header}:
                for p in predecessors[n]:
                    if p not in body:
                        fail(f"{self.name}+{n - self.start:#x}: a loop entered other than at its "
                             f"header (+{header - self.start:#x})")
        # A cycle with no back edge (irreducible flow) is not found here; the longest-path
        # search meets it as a cycle left after the loops are collapsed, and fails there.
        return loops


def longest(function, costs, bounds_of, report, functions_name=lambda address: hex(address),
            call_bound_of=lambda function, callee: None):
    """The longest path of function, with loops collapsed innermost first."""
    loops = function.loops()
    per_call_extra = 0
    shared_runs = {}  # a group of per-call loops sharing one bound -> (bound, longest turn)
    # A callee with a call-count bound costs nothing at its sites; the function pays it that
    # many times, once per call.
    counted = {}
    for v in function.blocks.values():
        for c in v["calls"] + v["tails"]:
            if c not in counted:
                counted[c] = call_bound_of(function, c)
    for c, calls in counted.items():
        if calls is not None:
            per_call_extra += calls * costs[c]
    # Nodes: blocks; edges with weights; node cost = block cost + its calls' bounds.
    node_cost = {}
    for b, v in function.blocks.items():
        node_cost[b] = v["cost"] + sum(costs[c] for c in v["calls"] + v["tails"]
                                       if counted[c] is None)
    edges = {b: {s: 0 for s in v["successors"]} for b, v in function.blocks.items()}
    exits = {b: 0 for b, v in function.blocks.items() if v["exits"]}
    members = {b: {b} for b in function.blocks}  # node -> blocks it stands for
    headers = sorted(loops)
    ordinal = {h: k for k, h in enumerate(headers)}
    for header in sorted(headers, key=lambda h: len(loops[h])):
        body_blocks = loops[header]
        body = {n for n in edges if members[n] & body_blocks}
        leaves = any(s not in body for n in body for s in edges[n]) or any(n in exits
                                                                             for n in body)
        # A loop with no way out ends the run (a fatal error's halt): no bound, no path on.
        fact = bounds_of(function, ordinal[header], header) if leaves else (0, False)
        bound, per_call = fact[0], fact[1]
        shared = fact[2] if len(fact) > 2 else None
        # Longest path from the header within the body, back edges to the header cut.
        dist = {}

        def reach(n, stack=()):
            if n in dist:
                return dist[n]
            if n in stack:
                fail(f"{function.name}: a cycle inside the loop at +{header - function.start:#x} "
                     f"that is not a loop of its own")
            best = None
            for p in body:
                if n in edges[p] and n != header:
                    d = reach(p, stack + (n,))
                    if d is not None:
                        w = d + edges[p][n] + node_cost[n]
                        best = w if best is None or w > best else best
            if n == header:
                best = node_cost[n]
            dist[n] = best
            return best

        for n in body:
            reach(n)
        turn = max((dist[n] + w for n in body for s, w in edges[n].items() if s == header),
                   default=0)
        per_call_bound = bound
        if per_call:
            # The bound holds for all entries of one call together and counts every run of the
            # body, a partial one that leaves it from inside included: each run is charged the
            # longer of a turn and a way out through the body, once per call of the function,
            # and each entry only the header's own way out (its test that ends the loop).
            partial = max([dist[n] + w for n in body if n != header
                           for s, w in edges[n].items() if s not in body] +
                          [dist[n] + exits[n] for n in body if n != header and n in exits],
                          default=0)
            turn = max(turn, partial)
            if shared is None:
                per_call_extra += bound * turn
            else:
                # Runs of every loop of the group count against the one bound: each is charged
                # the longest turn of the group, once per call.
                if shared in shared_runs and shared_runs[shared][0] != bound:
                    fail(f"{function.name}: the loops sharing '{shared}' state different bounds")
                shared_runs[shared] = (bound, max(turn, shared_runs.get(shared, (0, 0))[1]))
            bound = 0
        node = ("loop", header)
        node_cost[node] = 0
        edges[node] = {}
        for n in body:
            # With a per-call bound a way out from inside the body is a run already charged.
            inside = per_call and n != header
            for s, w in edges[n].items():
                if s not in body:
                    weight = 0 if inside else bound * turn + dist[n] + w
                    edges[node][s] = max(edges[node].get(s, 0), weight)
            if n in exits:
                weight = 0 if inside else bound * turn + dist[n] + exits[n]
                exits[node] = max(exits.get(node, 0), weight)
        for p in list(edges):
            if p in body or p == node:
                continue
            if header in edges[p]:
                edges[p][node] = max(edges[p].get(node, 0), edges[p].pop(header))
        members[node] = set().union(*(members[n] for n in body))
        for n in body:
            del edges[n]
            del node_cost[n]
            exits.pop(n, None)
            members.pop(n)
        entry_node = node if header == function.entry else None
        if entry_node is not None:
            function.entry_node = entry_node
        if leaves:
            inside = [h for h in headers if h != header and loops[h] > body_blocks]
            calls = sorted({functions_name(c) for b in body_blocks
                            for c in function.blocks[b]["calls"]})
            report.append({"function": function.name, "header": ordinal[header],
                           "address": f"{header:#x}", "bound": bound or per_call_bound,
                           "per_call": per_call, "shared": shared, "turn": turn,
                           "inside": [ordinal[h] for h in inside], "calls": calls})
    entry = getattr(function, "entry_node", function.entry)
    memo = {}

    def from_node(n, stack=()):
        if n in memo:
            return memo[n]
        if n in stack:
            fail(f"{function.name}: a cycle left after the loops were collapsed")
        best = exits.get(n)
        for s, w in edges[n].items():
            d = from_node(s, stack + (n,))
            if d is not None:
                d += w
                best = d if best is None or d > best else best
        memo[n] = None if best is None else best + node_cost[n]
        return memo[n]

    total = from_node(entry)
    if total is None:
        fail(f"{function.name}: no path reaches a return")
    per_call_extra += sum(bound * turn for bound, turn in shared_runs.values())
    return total + per_call_extra


def evaluate(expression, constants, where):
    """An integer from a bound: a number, or +, -, *, //, ** and parentheses over constants."""
    def value(node):
        if isinstance(node, ast.Constant) and isinstance(node.value, int):
            return node.value
        if isinstance(node, ast.Name):
            if node.id not in constants:
                fail(f"{where}: constant {node.id} is not listed under \"constants\"")
            return constants[node.id]
        if isinstance(node, ast.BinOp):
            operations = {ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b,
                          ast.Mult: lambda a, b: a * b, ast.FloorDiv: lambda a, b: a // b,
                          ast.Pow: lambda a, b: a**b}
            if type(node.op) in operations:
                return operations[type(node.op)](value(node.left), value(node.right))
        fail(f"{where}: cannot evaluate {expression!r}")

    if isinstance(expression, int):
        return expression
    return value(ast.parse(str(expression), mode="eval").body)


def read_constants(spec, spec_path, repository):
    """Each constant's value, read from its source file's `NAME = value;`."""
    constants = {}
    for name, path in spec.get("constants", {}).items():
        try:
            text = open(os.path.join(repository, path)).read()
        except OSError as error:
            fail(f"{spec_path}: constant {name}: {error}")
        m = re.search(rf"\b{re.escape(name)}\s*=\s*(\d+)u?\s*;", text)
        if not m:
            fail(f"{spec_path}: {name} = <integer>; not found in {path}")
        constants[name] = int(m.group(1))
    return constants


def register_at_call(function, block, call_address, register):
    """The constant a register holds at a call, from the calling block's moves, or None."""
    known = {}
    for address, mnemonic, operands in function.code:
        if address < block["first"]:
            continue
        if address >= call_address:
            break
        parts = [p.strip() for p in operands.split(",")]
        stem = mnemonic.split(".")[0]
        if not parts or not re.fullmatch(r"r\d+|ip|lr", parts[0]):
            continue
        target = parts[0]
        if stem in ("movs", "mov", "movw") and len(parts) == 2 and parts[1].startswith("#"):
            known[target] = int(parts[1][1:].split()[0], 0)
        elif stem in ("movs", "mov") and len(parts) == 2 and parts[1] in known:
            known[target] = known[parts[1]]
        elif stem in ("lsls", "lsl") and len(parts) == 3 and parts[1] in known and \
                parts[2].startswith("#"):
            known[target] = known[parts[1]] << int(parts[2][1:])
        elif stem in ("str", "strb", "strh", "cmp", "tst", "cmn", "push", "stmia", "vstr",
                      "vcmp", "vcmpe", "strd"):
            continue
        else:
            known.pop(target, None)
    return known.get(register)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("elf")
    parser.add_argument("root")
    parser.add_argument("--bounds", help="the loop-bounds file (JSON)")
    parser.add_argument("--target", help="the section of the bounds file for this ELF")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="take a constant as this value (e.g. max_gap=0: a frame after no gap)")
    parser.add_argument("--list-loops", action="store_true")
    parser.add_argument("--bound-only", action="store_true",
                        help="print the instructions bound alone, not the JSON report")
    args = parser.parse_args()
    info = read_elf(args.elf)
    by_name = {f["name"]: a for a, f in info.items()}
    if args.root not in by_name:
        fail(f"{args.elf}: no function named {args.root}")
    spec = {}
    if args.bounds:
        try:
            with open(args.bounds) as f:
                spec = json.load(f)
        except (OSError, ValueError) as error:
            fail(f"{args.bounds}: {error}")
        if args.target:
            if args.target not in spec.get("targets", {}):
                fail(f"{args.bounds}: no target {args.target}")
            target = spec["targets"][args.target]
        else:
            target = {}
        repository = os.path.dirname(os.path.abspath(args.bounds))
        while repository != "/" and not os.path.isdir(os.path.join(repository, ".git")) and \
                not os.path.isdir(os.path.join(repository, "lib")):
            repository = os.path.dirname(repository)
        constants = read_constants(spec, args.bounds, repository)
    else:
        target, constants = {}, {}
    for assignment in args.set:
        name, _, value = assignment.partition("=")
        if name not in constants or not value.isdigit():
            fail(f"--set {assignment}: not NAME=INTEGER with NAME a constant of the bounds file")
        constants[name] = int(value)
    table = target.get("loops", [])
    used = set()
    call_table = target.get("calls", [])
    calls_used = set()
    call_facts = {}  # (function, callee) -> its row in the report

    def bounds_of(function, ordinal, header):
        for k, entry in enumerate(table):
            if re.match(entry["function"], function.name) and entry["header"] == ordinal:
                used.add(k)
                if "shared" in entry and not entry.get("per_call", False):
                    fail(f"{args.bounds}: {entry['function']} loop {ordinal}: a shared bound "
                         f"must be per call")
                return (evaluate(entry["bound"], constants,
                                 f"{args.bounds}: {entry['function']} loop {ordinal}"),
                        entry.get("per_call", False), entry.get("shared"))
        if args.list_loops:
            return 1, False
        fail(f"{function.name}: loop {ordinal} at {header:#x} has no bound in "
             f"{args.bounds or 'a bounds file'}")

    def call_bound_of(function, callee):
        for k, entry in enumerate(call_table):
            if re.match(entry["function"], function.name) and \
                    re.match(entry["callee"], info[callee]["name"]):
                calls_used.add(k)
                bound = evaluate(entry["bound"], constants,
                                 f"{args.bounds}: {entry['function']} calls {entry['callee']}")
                call_facts[(function.name, callee)] = {
                    "function": function.name, "callee": info[callee]["name"], "bound": bound,
                    "why": entry.get("why", "")}
                return bound
        return None

    functions, order = {}, []

    def visit(address, path=()):
        if address in path:
            fail(f"recursion through {info[address]['name']}")
        if address in functions:
            return
        f = Function(address, info[address], info)
        functions[address] = f
        for c in sorted(f.calls):
            visit(c, path + (address,))
        order.append(address)

    visit(by_name[args.root])
    # A library routine whose loops run on a length argument: every call must pass a constant
    # no larger than the length its bounds assume.
    arguments = target.get("arguments", {})
    for f in functions.values():
        for block in f.blocks.values():
            for call_address, callee in block["call_sites"]:
                rule = arguments.get(info[callee]["name"])
                if rule is None:
                    continue
                value = register_at_call(f, block, call_address, rule["register"])
                if value is None or value > rule["at_most"]:
                    fail(f"{f.name}+{call_address - f.start:#x}: {info[callee]['name']} called "
                         f"with {rule['register']} = {value if value is not None else 'unknown'}, "
                         f"where its loop bounds assume a constant <= {rule['at_most']}")
    costs, loops = {}, []
    for address in order:
        costs[address] = longest(functions[address], costs, bounds_of, loops,
                                 lambda c: re.sub(r"^_ZN?K?9stickslip", "", info[c]["name"])[:40],
                                 call_bound_of)
    if args.list_loops:
        json.dump(loops, sys.stdout, indent=1)
        sys.stdout.write("\n")
        return
    for k, entry in enumerate(table):
        analysed = any(re.match(entry["function"], f.name) for f in functions.values())
        if analysed and k not in used:
            fail(f"{args.bounds}: {args.target}: no loop matches {entry['function']} header "
                 f"{entry['header']}: the code changed, so the table must be checked again")
    for k, entry in enumerate(call_table):
        analysed = any(re.match(entry["function"], f.name) for f in functions.values())
        if analysed and k not in calls_used:
            fail(f"{args.bounds}: {args.target}: {entry['function']} makes no call that matches "
                 f"{entry['callee']}: the code changed, so the table must be checked again")
    for entry in loops:
        for k, row in enumerate(table):
            if re.match(row["function"], entry["function"]) and row["header"] == entry["header"]:
                entry["why"] = row.get("why", "")
    if args.bound_only:
        print(costs[by_name[args.root]])
        return
    json.dump({"root": args.root, "instructions_bound": costs[by_name[args.root]],
               "constants": constants,
               "functions": {functions[a].name: costs[a] for a in order},
               "loops": loops,
               "calls": [dict(fact, callee_bound=costs[callee])
                         for (_, callee), fact in call_facts.items()]}, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
