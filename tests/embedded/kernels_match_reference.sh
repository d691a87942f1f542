#!/usr/bin/env bash
# The fixed-point kernels as each cross build compiles them against reference code of the same
# build (port/baremetal/src/kernel_check.cpp), on QEMU's mps2 boards: the Cortex-M0+ build (its
# ARMv6-M code, with the saturating add in inline assembly) on mps2-an385, the Cortex-M4F build on
# mps2-an386.
#   tests/embedded/kernels_match_reference.sh CROSS_ROOT
# CROSS_ROOT: the preset build directories of tools/check-embedded.sh. Fails unless every
# kernel's line reports cases and no mismatch, the sum's and the product's cases include
# saturating ones, and the run exits 0.
set -euo pipefail
cross_root=$1
status=0
for preset in cortex-m0plus cortex-m4f; do
  case $preset in
    cortex-m0plus) machine=mps2-an385 ;;
    cortex-m4f) machine=mps2-an386 ;;
  esac
  elf=$cross_root/$preset/port/baremetal/stickslip_kernel_check.elf
  if [ ! -f "$elf" ]; then
    echo "kernels_match_reference: $elf is missing (CTest embedded.cross_builds_without_heap builds it)" >&2
    exit 1
  fi
  run_status=0
  output=$(timeout 300 qemu-system-arm -M "$machine" -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -kernel "$elf" 2>&1) || run_status=$?
  sed "s/^/$preset: /" <<<"$output"
  kernels=$(grep -c '^kernel_check: .* cases=[1-9][0-9]* saturated=[0-9]* mismatched=0$' <<<"$output" || true)
  # The sum and the product must meet their saturation too, the rare path the flags take.
  saturating=$(grep -c '^kernel_check: \(add\|multiply\).* saturated=[1-9]' <<<"$output" || true)
  if [ "$run_status" -ne 0 ] || [ "$kernels" -ne 3 ] || [ "$saturating" -ne 2 ]; then
    echo "kernels_match_reference: $preset: exit status $run_status, $kernels of 3 kernels match, $saturating of 2 saturate" >&2
    status=1
  fi
done
exit $status
