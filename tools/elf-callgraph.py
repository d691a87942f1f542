#!/usr/bin/env python3
"""Code size and worst-case stack of the functions reachable from a root, read from an ARM ELF.

    tools/elf-callgraph.py ELF ROOT [ROOT...]

Disassembles ELF with arm-none-eabi-objdump and takes, for every function symbol, its size (nm),
its stack frame (push/vpush registers + `sub sp, #n` in its body) and its calls (bl/blx/b to
another function's start: calls and tail calls). Prints a JSON object: for each root, the
functions reachable from it with their sizes, the total code size, and the deepest call chain
with its stack (frames summed; a tail call reuses the caller's frame). Indirect calls (blx rN)
are listed, since their targets cannot be followed."""
import json
import re
import subprocess
import sys


def read_functions(elf):
    nm = subprocess.run(["arm-none-eabi-nm", "-S", elf], check=True, capture_output=True,
                        text=True).stdout
    functions = {}
    for line in nm.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "TtWw":
            address = int(parts[0], 16) & ~1
            functions.setdefault(address, {"name": parts[3], "size": int(parts[1], 16)})
    return functions


def analyse(elf):
    functions = read_functions(elf)
    dump = subprocess.run(["arm-none-eabi-objdump", "-d", "--no-show-raw-insn", elf], check=True,
                          capture_output=True, text=True).stdout
    header = re.compile(r"^([0-9a-f]+) <(.+)>:$")
    instruction = re.compile(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$")
    current = None
    for line in dump.splitlines():
        m = header.match(line)
        if m:
            address = int(m.group(1), 16)
            current = functions.get(address)
            if current is not None:
                current.update(frame=0, calls=set(), tail_calls=set(), indirect=False)
            continue
        m = instruction.match(line)
        if not m or current is None:
            continue
        mnemonic, operands = m.group(2), m.group(3)
        if mnemonic in ("push", "push.w", "stmdb") and "{" in operands:
            registers = operands[operands.index("{") + 1:operands.index("}")]
            count = 0
            for item in registers.split(","):
                item = item.strip()
                if "-" in item:
                    lo, hi = item.split("-")
                    count += int(hi.strip()[1:]) - int(lo.strip()[1:]) + 1
                elif item:
                    count += 1
            if mnemonic != "stmdb" or operands.startswith("sp!"):
                current["frame"] += 4 * count
        elif mnemonic == "vpush":
            registers = operands[operands.index("{") + 1:operands.index("}")]
            size = 8 if registers.strip().startswith("d") else 4
            count = 0
            for item in registers.split(","):
                item = item.strip()
                if "-" in item:
                    lo, hi = item.split("-")
                    count += int(hi.strip()[1:]) - int(lo.strip()[1:]) + 1
                elif item:
                    count += 1
            current["frame"] += size * count
        elif mnemonic in ("sub", "sub.w", "subw") and re.match(r"sp,\s*(sp,\s*)?#", operands):
            current["frame"] += int(re.search(r"#(\d+)", operands).group(1))
        elif mnemonic in ("bl", "blx", "b", "b.w", "b.n"):
            target = re.match(r"([0-9a-f]+) <", operands)
            if target:
                address = int(target.group(1), 16)
                if address in functions and functions[address] is not current:
                    (current["calls"] if mnemonic.startswith("bl") else current["tail_calls"]).add(address)
            elif mnemonic == "blx":
                current["indirect"] = True
    return functions


def report(functions, root_name):
    by_name = {f["name"]: a for a, f in functions.items()}
    roots = [a for a, f in functions.items() if f["name"] == root_name or f["name"].startswith(root_name + ".")]
    if root_name in by_name:
        roots = [by_name[root_name]]
    if not roots:
        raise SystemExit(f"elf-callgraph: no function named {root_name}")
    seen, stack = set(), list(roots)
    while stack:
        address = stack.pop()
        if address in seen:
            continue
        seen.add(address)
        f = functions[address]
        stack.extend(f.get("calls", ()))
        stack.extend(f.get("tail_calls", ()))
    memo = {}

    def deepest(address, path=()):
        if address in path:
            return (float("inf"), [functions[address]["name"] + " (recursion)"])
        if address in memo:
            return memo[address]
        f = functions[address]
        frame = f.get("frame", 0)
        best = (frame, [f"{f['name']} ({frame} B)"])
        for callee in f.get("calls", ()):
            depth, chain = deepest(callee, path + (address,))
            if frame + depth > best[0]:
                best = (frame + depth, [f"{f['name']} ({frame} B)"] + chain)
        for callee in f.get("tail_calls", ()):
            # A tail call replaces this frame.
            depth, chain = deepest(callee, path + (address,))
            if depth > best[0]:
                best = (depth, [f"{f['name']} ({frame} B, tail call)"] + chain)
        memo[address] = best
        return best

    depth, chain = max((deepest(r) for r in roots), key=lambda x: x[0])
    members = sorted(((functions[a]["name"], functions[a]["size"]) for a in seen),
                     key=lambda x: -x[1])
    return {
        "root": root_name,
        "code_bytes": sum(size for _, size in members),
        "functions": [{"name": n, "bytes": s} for n, s in members],
        "stack_bytes": depth,
        "stack_chain": chain,
        "indirect_calls": sorted(functions[a]["name"] for a in seen if functions[a].get("indirect")),
    }


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    functions = analyse(sys.argv[1])
    json.dump([report(functions, root) for root in sys.argv[2:]], sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
