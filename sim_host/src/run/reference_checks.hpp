// The checks the reference solver (reference_solver.hpp) makes, with and without end stops: of its
// inputs, and of the events in one sample interval. Private to the run library.
#pragma once

#include <cstddef>
#include <vector>

namespace stickslip::host::reference {

// Throws HostError naming the first bad value: no input samples, a non-finite a_u or actuator
// force, an actuator history whose length is not the input's (empty means none), or a
// non-finite initial state.
void check_inputs(const std::vector<double>& a_u, const std::vector<double>& f_a_n, double x0_m,
                  double v0_m_per_s);

// Counts one more event in the sample interval ending at `sample`; throws HostError, naming the
// sample and its time, where that makes more than kMaxEventsPerSample (reference_closed_form.hpp).
void count_sample_event(int& events_in_sample, std::size_t sample, double dt_s);

}  // namespace stickslip::host::reference
