// Exact references for the fixed-point kernels, free of the test framework so that the host's
// tests and the firmware's kernel check on QEMU (port/baremetal/src/kernel_check.cpp) hold the
// kernels to one definition.
#pragma once

namespace stickslip::test {

// round(a b / 2^fraction_bits), ties away from zero, in an integer type wide enough for a b:
// the exact reference for a fixed-point product.
template <int kFractionBits, typename Wide>
constexpr Wide rounded_product(Wide a, Wide b) {
  const Wide p = a * b;
  const Wide magnitude = p < 0 ? -p : p;
  const Wide q = (magnitude + (Wide{1} << (kFractionBits - 1))) >> kFractionBits;
  return p < 0 ? -q : q;
}

}  // namespace stickslip::test
