// stickslip._stickslip: the host library's simulate runner, recording readers and generators, and
// the core's oscillator and observer, for numpy arrays. The Python package (python/stickslip/)
// wraps these with keyword arguments and turns the statistics JSON into a dict. Arrays cross the
// boundary without per-sample Python work; every run releases the GIL.
#include "module.hpp"

#include <exception>

PYBIND11_MODULE(_stickslip, m) {
  using namespace stickslip::python;
  m.doc() = "stickslip's C++ core and host library (use the stickslip package)";

  // Every bad argument or bad file is a HostError with a complete one-line message.
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const HostError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  bind_runs(m);
  bind_readers(m);
  bind_oscillator(m);  // before the observer: its estimates hold a Step
  bind_observer(m);
}
