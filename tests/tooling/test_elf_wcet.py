#!/usr/bin/env python3
"""tools/elf-wcet.py's longest path against every execution of small control-flow graphs.

Each graph is a function of basic blocks with instruction counts; an execution is any walk from
the entry to a return that keeps the loop bounds of the table (a loop's back edge taken at most
bound - 1 times per entry; a per-call loop's body run at most bound times per call of the
function, a run that returns from inside the body included). The analysis must bound the costliest
execution (it is sound) and, where its rules are exact for the graph, equal it. The graphs are
the shapes of the firmware's step: a counted loop, a loop nested in another, and slip()'s block
walk, a per-call loop inside the event loop whose body can return an event.
"""
import importlib.util
import os
import sys

sys.dont_write_bytecode = True  # nothing written into the source tree
here = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    "elf_wcet", os.path.join(here, "..", "..", "tools", "elf-wcet.py"))
wcet = importlib.util.module_from_spec(spec)
spec.loader.exec_module(wcet)


def function(name, costs, successors, returns, calls=None):
    """A Function of blocks named by integers: costs {block: n}, successors {block: [..]}, calls
    {block: [callee, ..]} (callees named by strings)."""
    f = object.__new__(wcet.Function)
    f.name, f.start, f.entry = name, 0, min(costs)
    f.blocks = {b: {"cost": c, "calls": list((calls or {}).get(b, [])), "tails": [],
                    "successors": successors.get(b, []), "exits": b in returns}
                for b, c in costs.items()}
    return f


def analysed(f, bounds, callees=None, call_bounds=None):
    """The analysis's bound: bounds {header block: (bound, per_call[, shared])}, callees
    {callee: its bound}, call_bounds {callee: the most calls per call of f} (a call-count
    fact)."""
    def bounds_of(function_, ordinal, header):
        return bounds[header]

    def call_bound_of(function_, callee):
        return (call_bounds or {}).get(callee)
    return wcet.longest(f, dict(callees or {}), bounds_of, [], str, call_bound_of)


def costliest(f, bounds, callees=None, call_bounds=None):
    """The costliest execution, by walking every one the bounds allow (each callee costing its
    bound, called at most call_bounds[callee] times)."""
    loops = f.loops()
    callees, call_bounds = callees or {}, call_bounds or {}
    best = [0]

    def walk(block, cost, back_edges, runs, calls=()):
        cost += f.blocks[block]["cost"]
        for callee in f.blocks[block]["calls"]:
            cost += callees[callee]
            calls = calls + (callee,)
            if calls.count(callee) > call_bounds.get(callee, len(calls)):
                return
        if f.blocks[block]["exits"]:
            best[0] = max(best[0], cost)
        for s in f.blocks[block]["successors"]:
            b_edges, b_runs = dict(back_edges), dict(runs)
            ok = True
            for header, body in loops.items():
                bound, per_call = bounds[header][:2]
                runs_key = bounds[header][2] if len(bounds[header]) > 2 else header
                if s == header and block in body:  # a back edge
                    b_edges[header] = b_edges.get(header, 0) + 1
                    if not per_call and b_edges[header] > bound - 1:
                        ok = False
                if s == header and block not in body:  # an entry: its count starts again
                    b_edges[header] = 0
                if block == header and s in body and s != header:  # a run of the body
                    b_runs[runs_key] = b_runs.get(runs_key, 0) + 1
                    if per_call and b_runs[runs_key] > bound:
                        ok = False
            if ok:
                walk(s, cost, b_edges, b_runs, calls)

    walk(f.entry, 0, {}, {})
    return best[0]


failures = []


def check(name, f, bounds, exact, below=None, callees=None, call_bounds=None):
    """exact: the analysis equals the costliest execution; below: it exceeds it by less."""
    bound = analysed(f, bounds, callees, call_bounds)
    worst = costliest(f, bounds, callees, call_bounds)
    verdict = "ok" if bound >= worst and (bound == worst or not exact) else "FAILED"
    if below is not None and bound - worst >= below:
        verdict = f"FAILED (more than {below - 1} above)"
    print(f"{name}: analysis {bound}, costliest execution {worst}: {verdict}")
    if verdict != "ok":
        failures.append(name)
    return bound


# A counted loop: entry 1, header 2 (its test), body 10, way out 3. The analysis charges each
# run a whole turn and the way out on top, one turn more than the body can run: safe, not exact.
counted = function("counted", {1: 1, 2: 2, 3: 10, 4: 3}, {1: [2], 2: [3, 4], 3: [2]}, {4})
check("counted loop", counted, {2: (5, False)}, exact=False)

# Nested: an outer loop (header 2) whose body holds an inner loop (header 3).
nested = function("nested", {1: 1, 2: 2, 3: 2, 4: 7, 5: 4, 6: 1},
                  {1: [2], 2: [3, 6], 3: [4, 5], 4: [3], 5: [2]}, {6})
check("nested loops", nested, {2: (3, False), 3: (4, False)}, exact=False)

# slip()'s block walk inside the event loop: the event loop (header 2, at most 4 passes) either
# takes a stuck pass (block 3) or enters the walk (header 4) whose body (block 5, the block map
# and the tick's root search) returns an event (block 6) or goes on (back to 4); the walk's test
# leads on to the pass's end (block 7). At most one run of the walk's body per call: the body's
# cost (100) may be charged once, so the analysis stays within less than one body of the
# costliest execution (charging each entry a way out through the body, it did not).
walk = function("walk", {1: 1, 2: 2, 3: 5, 4: 2, 5: 100, 6: 4, 7: 6, 8: 1},
                {1: [2], 2: [3, 4, 8], 3: [2], 4: [5, 7], 5: [4, 6], 7: [2]}, {6, 8})
per_call = check("per-call walk that returns from inside its body", walk,
                 {2: (4, False), 4: (1, True)}, exact=False, below=100)
per_entry = analysed(walk, {2: (4, False), 4: (1, False)})
# Charging the walk per pass would count its body once per pass of the event loop.
if not per_call < per_entry:
    print(f"per-call walk: {per_call}, not below the per-entry charge {per_entry}: FAILED")
    failures.append("per-call charge")
else:
    print(f"per-call walk: {per_call} against {per_entry} charged per pass: ok")
# With a bound of 2 runs per call, both may return or go on.
check("per-call walk, two runs", walk, {2: (4, False), 4: (2, True)}, exact=False, below=100)

# A call that only some passes of a loop make, with a call-count fact: the event loop (header 2,
# at most 4 passes) takes a stuck pass (block 3) or a slip pass (block 4) that calls the tick's
# root search F (cost 1000), and the way out (block 6) calls it too; at most 3 calls of F per
# call of the function (step_sticking(): the non-detecting pass and the first one, at the step's
# start, make none at L = 0). Charged 3 times once, not once per pass: within less than two turns
# of the loop (15) of the costliest execution (one the slack of every counted loop, above),
# where charging every site would add a call per pass.
search = function("search", {1: 1, 2: 2, 3: 5, 4: 10, 5: 3, 6: 2, 7: 1},
                  {1: [2], 2: [3, 4, 6], 3: [2], 4: [5], 5: [2], 6: [7]}, {7}, {4: ["F"], 6: ["F"]})
counted_calls = check("a callee called at most 3 times from a loop and its way out", search,
                      {2: (4, False)}, exact=False, below=30, callees={"F": 1000},
                      call_bounds={"F": 3})
every_site = analysed(search, {2: (4, False)}, {"F": 1000})
if not counted_calls + 1000 < every_site:
    print(f"call-count fact: {counted_calls}, not a call below charging every site "
          f"({every_site}): FAILED")
    failures.append("call-count charge")
else:
    print(f"call-count fact: {counted_calls} against {every_site} charged at every site: ok")
# Sound only with the fact's own count: the costliest execution with 4 calls exceeds the
# analysis told 3.
if not costliest(search, {2: (4, False)}, {"F": 1000}, {"F": 4}) > counted_calls:
    print("call-count fact: a fourth call fits the analysis of three: FAILED")
    failures.append("call-count soundness")

# One event loop of the source that the compiler split in two (as GCC may split a step's
# passes): the event loop (header 2, its slip pass, block 3, may return from inside) and, after
# its way out (block 6), a loop of stuck passes (header 5, body 8) that ends the step. Their runs together are at most 4 per call: a
# shared per-call bound charges 4 of the longer turn once, where a bound of 4 on each would
# charge 8 passes.
passes = function("shared passes", {1: 1, 2: 2, 3: 50, 6: 4, 5: 2, 7: 3, 8: 20, 9: 1},
                  {1: [2], 2: [3, 6], 3: [2, 7], 6: [5], 5: [8, 9], 8: [5]}, {7, 9})
shared_bound = check("per-call loops sharing one bound", passes,
                     {2: (4, True, "passes"), 5: (4, True, "passes")}, exact=True)
separate = analysed(passes, {2: (4, True), 5: (4, True)})
if not shared_bound + 3 * 20 < separate:
    print(f"shared bound: {shared_bound}, not below charging each loop its own ({separate}): "
          "FAILED")
    failures.append("shared charge")
else:
    print(f"shared bound: {shared_bound} against {separate} with a bound per loop: ok")
# Sound only with the shared count: with 4 runs of each loop an execution exceeds it.
unshared_worst = costliest(passes, {2: (4, True), 5: (4, True)})
if not unshared_worst > shared_bound:
    print("shared bound: 4 runs of each loop fit the analysis of 4 in all: FAILED")
    failures.append("shared soundness")
else:
    print(f"shared bound: 4 runs of each loop reach {unshared_worst}, above it: ok")

if failures:
    sys.stderr.write(f"test_elf_wcet: {len(failures)} failed: {', '.join(failures)}\n")
    sys.exit(1)
