#!/usr/bin/env bash
# Configures and builds the cross presets cortex-m4f and cortex-m0plus in BUILD_ROOT/<preset>
# (default: build/embedded-check), then checks every ELF they make:
#   - no heap and no C++ runtime: no malloc/free/calloc/realloc/_sbrk, operator new/delete,
#     __cxa_* (exceptions, guards, atexit), unwinder or personality routine in the symbol table;
#   - the ABI the preset asks for: Cortex-M4F passes floats in FPU registers, Cortex-M0+ is
#     ARMv6-M;
#   - the Cortex-M0+ firmware's step (everything reachable from stickslip_seat_step, the seat's
#     step the ECU node calls, read from the disassembly by tools/elf-callgraph.py) within its
#     budget: code <= 4096 B, deepest stack <= 256 B; the whole receive callback's figures
#     (the node around the step) are printed too. A static measure of the ELF, not a timing: it cannot be noisy;
#   - every loop of the receive interrupt of both firmware builds (and of their end-stop builds)
#     has a bound in
#     port/baremetal/loop-bounds.json (tools/elf-wcet.py fails on a loop without one, on control
#     flow it cannot follow, and on a bound that no longer matches a loop), and the static bounds
#     on the instructions of one step and of one frame are printed; the analysis is also checked
#     to refuse a loop left without a bound.
# Exit status 0 when everything builds and passes. Used by CTest (label embedded).
set -euo pipefail

source_dir=$(cd "$(dirname "$0")/.." && pwd)
build_root=${1:-$source_dir/build/embedded-check}
jobs=${STICKSLIP_JOBS:-2}

for tool in arm-none-eabi-g++ arm-none-eabi-nm arm-none-eabi-readelf; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "check-embedded: $tool not found; run tools/install-deps.sh (gcc-arm-none-eabi, libnewlib-arm-none-eabi, libstdc++-arm-none-eabi-newlib)" >&2
    exit 1
  fi
done

forbidden='^(malloc|free|calloc|realloc|reallocf|memalign|_malloc_r|_free_r|_calloc_r|_realloc_r|_sbrk|_sbrk_r|_Znw.*|_Zna.*|_Zdl.*|_Zda.*|__cxa_.*|__gxx_personality.*|_Unwind_.*|__aeabi_unwind_cpp_pr.*)$'
mkdir -p "$build_root"
status=0
for preset in cortex-m4f cortex-m0plus; do
  dir=$build_root/$preset
  (cd "$source_dir" && cmake --preset "$preset" -B "$dir" >"$build_root/$preset.configure.log" 2>&1) || {
    cat "$build_root/$preset.configure.log" >&2
    echo "check-embedded: $preset: configure failed" >&2
    exit 1
  }
  cmake --build "$dir" -j "$jobs" >"$build_root/$preset.build.log" 2>&1 || {
    cat "$build_root/$preset.build.log" >&2
    echo "check-embedded: $preset: build failed" >&2
    exit 1
  }
  mapfile -t elves < <(find "$dir" -name '*.elf' -type f | sort)
  if [ ${#elves[@]} -eq 0 ]; then
    echo "check-embedded: $preset: no ELF built" >&2
    exit 1
  fi
  for elf in "${elves[@]}"; do
    name=${elf#"$build_root"/}
    hits=$(arm-none-eabi-nm "$elf" | awk '{print $NF}' | grep -E "$forbidden" || true)
    if [ -n "$hits" ]; then
      echo "check-embedded: $name links heap or C++ runtime symbols:" $hits >&2
      status=1
    else
      echo "check-embedded: $name: no heap, no C++ runtime symbols"
    fi
    attributes=$(arm-none-eabi-readelf -A "$elf")
    case $preset in
      cortex-m4f) expected='Tag_ABI_VFP_args: VFP registers' ;;
      cortex-m0plus) expected='Tag_CPU_arch: v6S-M' ;;
    esac
    if ! grep -q "$expected" <<<"$attributes"; then
      echo "check-embedded: $name: expected '$expected' in its build attributes" >&2
      status=1
    fi
  done
done

firmware=$build_root/cortex-m0plus/port/baremetal/stickslip_firmware.elf
# The budget is the seat's step's (stickslip_seat_step); the whole receive callback (the lib/ ECU
# node around the step: receive checks, E2E, the output frames) is printed beside it.
figures() {  # root -> "code stack"
  python3 "$source_dir/tools/elf-callgraph.py" "$firmware" "$1" |
    python3 -c 'import json, sys; r = json.load(sys.stdin)[0]; print(r["code_bytes"], r["stack_bytes"])'
}
read -r code stack < <(figures stickslip_seat_step)
read -r node_code node_stack < <(figures stickslip_node_on_frame)
if [ "$code" -le 4096 ] && [ "$stack" -le 256 ]; then
  echo "check-embedded: cortex-m0plus step: $code B of code (<= 4096), $stack B of stack (<= 256)"
else
  echo "check-embedded: cortex-m0plus step: $code B of code, $stack B of stack; the budget is 4096 B and 256 B" >&2
  status=1
fi
echo "check-embedded: cortex-m0plus receive callback (ECU node and step): $node_code B of code, $node_stack B of stack"

# Static bounds on the instructions of one step and of one received frame (the receive interrupt
# of the QEMU board, the region tools/qemu-worst-case.sh measures): after no gap, and after the
# longest gap the node holds (max_gap samples stepped in one frame).
# The same for the firmware with the end-stop seat (stickslip_firmware_qemu_end_stops.elf).
bound() {  # elf preset root [--set NAME=VALUE] -> instructions
  python3 "$source_dir/tools/elf-wcet.py" "$build_root/$2/port/baremetal/$1" "$3" \
    --bounds "$source_dir/port/baremetal/loop-bounds.json" --target "$2" --bound-only "${@:4}"
}
for elf in stickslip_firmware_qemu.elf stickslip_firmware_qemu_end_stops.elf; do
  for preset in cortex-m0plus cortex-m4f; do
    if step=$(bound "$elf" "$preset" stickslip_seat_step) &&
      frame=$(bound "$elf" "$preset" CAN0_IRQHandler --set max_gap=0) &&
      gap=$(bound "$elf" "$preset" CAN0_IRQHandler); then
      echo "check-embedded: $preset $elf static bound: $step instructions per step, $frame per frame after no gap, $gap after the longest gap held"
    else
      echo "check-embedded: $preset $elf: the static bound could not be derived (above)" >&2
      status=1
    fi
  done
done
# The analysis refuses a loop without a bound rather than guessing one.
if python3 "$source_dir/tools/elf-wcet.py" "$build_root/cortex-m0plus/port/baremetal/stickslip_firmware_qemu.elf" \
  stickslip_seat_step >/dev/null 2>&1; then
  echo "check-embedded: tools/elf-wcet.py gave a bound with no loop bounds at all" >&2
  status=1
fi
exit $status
