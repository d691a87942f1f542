// Private to the module: what its files share (the keyword-argument spec, number formatting,
// numpy arrays over vectors, the one-step sample) and the function each file binds its part with.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/models/step_common.hpp"

namespace py = pybind11;

namespace stickslip::python {

using host::ConfigurationError;
using host::HostError;
using host::ScalarType;
using host::SimulationSetup;
using host::SimulationSummary;
using host::SimulationTrace;

std::string format_number(double value);

// Reserves room for `count` values that will be written once, right after. Fresh memory costs a
// page fault per 4 KB page on first touch, which on a virtual machine costs more than simulating
// the samples in it; asking for transparent huge pages (Linux, mode "madvise", as numpy does for
// its own arrays) makes that 512 times rarer. Advice only: without it the run is the same.
template <typename V>
void reserve_for_writing(std::vector<V>& values, std::size_t count) {
  if (values.capacity() >= count) return;  // memory a previous run wrote: no page faults
  values.reserve(count);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::size_t bytes = count * sizeof(V);
  if (bytes < (std::size_t{4} << 20)) return;
  const std::uintptr_t page = 4096, begin = reinterpret_cast<std::uintptr_t>(values.data());
  const std::uintptr_t start = (begin + page - 1) & ~(page - 1);
  const std::uintptr_t end = (begin + bytes) & ~(page - 1);
  if (end > start) ::madvise(reinterpret_cast<void*>(start), end - start, MADV_HUGEPAGE);
#endif
}

// Parameters: the keyword arguments of simulate(), resolved as `stickslip simulate` resolves its
// flags (the scene file first, then every argument given over it).
struct RunSpec {
  SimulationSetup setup;
  ScalarType scalar = ScalarType::float64;
  std::string scene_path;
  double scene_dt_s = 0.0;  // 0: the scene names no sample rate
};
RunSpec parse_spec(const py::dict& options);

// The core's message with the argument that sets the offending parameter named.
std::string explain_configuration_error(const std::string& core_message);

// numpy arrays that own a vector's memory (no copy).
template <typename V>
py::array owned_array(std::vector<V>&& values, py::dtype dtype) {
  auto* heap = new std::vector<V>(std::move(values));
  py::capsule owner(heap, [](void* pointer) { delete static_cast<std::vector<V>*>(pointer); });
  const py::ssize_t size = static_cast<py::ssize_t>(heap->size());
  return py::array(dtype, {size}, {static_cast<py::ssize_t>(sizeof(V))}, heap->data(), owner);
}

inline py::array float64_array(std::vector<double>&& values) {
  return owned_array(std::move(values), py::dtype::of<double>());
}

// t[n] = n dt, from the index (as the generator writes it), never accumulated.
std::vector<double> time_line(std::size_t count, double dt_s);

// Samples from any 1-D array-like; one memcpy when it is already contiguous float64. `expected`
// completes the message for anything else ("a_u: expected ...", `name` the argument).
std::vector<double> samples_from(const py::handle& values, const char* expected,
                                 const char* name = "a_u");

// A recording file as `stickslip simulate` reads it when given no recording flags
// (host::read_recording with default options: the t,a_u CSV, .mat, a logger's text): its one
// segment, with the actuator force of its column f_a (N) when it has one. A force that reading
// could not keep on its samples is refused with the command's message.
host::SampledSignal read_recording_file(const std::string& path);

py::dict signal_dict(std::vector<double>&& t, std::vector<double>&& a_u, double dt_s);

// One step's output (SI units), whatever the scalar.
struct Sample {
  double x_r = 0.0, v_r = 0.0, a_x = 0.0, f_f = 0.0, stuck_time = 0.0, stuck_fraction = 0.0;
  bool stuck = false;
  int events = 0;
};

template <typename T>
Sample sample_of(const StepOutput<T>& out) {
  return {static_cast<double>(out.x_r_m),
          static_cast<double>(out.v_r_m_per_s),
          static_cast<double>(out.a_x_m_per_s2),
          static_cast<double>(out.friction_n),
          static_cast<double>(out.stuck_time_s),
          static_cast<double>(out.stuck_fraction),
          out.stuck,
          out.events};
}

void bind_runs(py::module_& m);
void bind_readers(py::module_& m);
void bind_oscillator(py::module_& m);
void bind_observer(py::module_& m);

}  // namespace stickslip::python
