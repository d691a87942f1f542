// The checks every entry point of the reference solver (reference_solver.hpp) makes of its
// inputs, with and without end stops. Private to the run library.
#pragma once

#include <vector>

namespace stickslip::host::reference {

// Throws HostError naming the first bad value: no input samples, a non-finite a_u or actuator
// force, an actuator history whose length is not the input's (empty means none), or a
// non-finite initial state.
void check_inputs(const std::vector<double>& a_u, const std::vector<double>& f_a_n, double x0_m,
                  double v0_m_per_s);

}  // namespace stickslip::host::reference
