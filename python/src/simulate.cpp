// simulate() and simulate_batch(): exactly what `stickslip simulate` runs (simulate_signal*,
// add_ride_comfort, format_stats_json) on the same samples and actuator force, so the trace and
// statistics equal the command's bit for bit. The host's runner takes a std::vector, so the input
// is copied into one with a single memcpy; the outputs are moved into numpy arrays that own them
// (no copy). Every run releases the GIL.
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "module.hpp"
#include "stickslip/host/run/stats_json.hpp"

namespace stickslip::python {
namespace {

struct RunOutput {
  std::vector<double> x_r, v_r, a_x, f_f;
  std::vector<std::uint8_t> stuck;
  std::string stats_json;
  bool reference = false;
};

template <typename T>
std::vector<double> as_double(std::vector<T>&& values) {
  if constexpr (std::is_same_v<T, double>) {
    return std::move(values);
  } else {
    std::vector<double> converted;
    reserve_for_writing(converted, values.size());
    converted.assign(values.begin(), values.end());
    return converted;
  }
}

// The host's runner resizes the trace to the input's length: the room is made here first.
template <typename T>
void reserve_trace(SimulationTrace<T>& trace, std::size_t count) {
  reserve_for_writing(trace.x_r_m, count);
  reserve_for_writing(trace.v_r_m_per_s, count);
  reserve_for_writing(trace.a_x_m_per_s2, count);
  reserve_for_writing(trace.friction_n, count);
  reserve_for_writing(trace.stuck, count);
}

template <typename T>
void take_trace(RunOutput& output, SimulationTrace<T>& trace, bool keep) {
  if (!keep) return;
  output.x_r = as_double(std::move(trace.x_r_m));
  output.v_r = as_double(std::move(trace.v_r_m_per_s));
  output.a_x = as_double(std::move(trace.a_x_m_per_s2));
  output.f_f = as_double(std::move(trace.friction_n));
  output.stuck = std::move(trace.stuck);
}

// A thread's trace memory, kept between the runs of a batch that returns no traces: the host's
// runner then finds it sized and writes over it (every row of it, every run), so only the first
// run pays for fresh memory.
struct Scratch {
  SimulationTrace<double> trace;
  SimulationTrace<float> trace_float;
  std::vector<float> a_u_float;
};

// f_a: the actuator force (N) per sample, or empty for none (the plain step(a_u) loop).
RunOutput run_spec(const RunSpec& spec, const std::vector<double>& a_u,
                   const std::vector<double>& f_a, double dt_s, const std::string& input_label,
                   bool keep_trace, Scratch& scratch) {
  if (spec.scene_dt_s > 0.0 && std::fabs(dt_s - spec.scene_dt_s) > 1e-9 * spec.scene_dt_s) {
    throw HostError("dt = " + format_number(dt_s) + " s, but the scene " + spec.scene_path +
                    " has sample_rate_hz = " + format_number(1.0 / spec.scene_dt_s) +
                    " (dt = " + format_number(spec.scene_dt_s) + " s); resample(a_u, dt, " +
                    format_number(spec.scene_dt_s) + ") puts the recording on the scene's step");
  }
  SimulationSetup setup = spec.setup;
  setup.params.dt_s = dt_s;
  if (!f_a.empty()) setup.actuator_force_n = &f_a;
  RunOutput output;
  output.reference = setup.reference;
  SimulationSummary summary;
  try {
    if (spec.scalar == ScalarType::fixed || spec.scalar == ScalarType::fixed32) {
      SimulationTrace<double>& trace = scratch.trace;
      reserve_trace(trace, a_u.size());
      summary = spec.scalar == ScalarType::fixed ? host::simulate_signal_fixed(setup, a_u, trace)
                                                 : host::simulate_signal_fixed32(setup, a_u, trace);
      host::add_ride_comfort(summary, a_u, trace.a_x_m_per_s2, dt_s);
      take_trace(output, trace, keep_trace);
    } else if (spec.scalar == ScalarType::float32) {
      // Converted once, before the loop: the float run sees only floats (and only finite ones).
      // The force first at each sample, as the command checks it.
      for (std::size_t n = 0; n < a_u.size(); ++n) {
        if (!f_a.empty() && std::fabs(f_a[n]) > static_cast<double>(FLT_MAX)) {
          throw HostError("f_a = " + format_number(f_a[n]) + " at sample " + std::to_string(n) +
                          " is beyond the range of a float (scalar='float')");
        }
        if (std::fabs(a_u[n]) > static_cast<double>(FLT_MAX)) {
          throw HostError("a_u = " + format_number(a_u[n]) + " at sample " + std::to_string(n) +
                          " is beyond the range of a float (scalar='float')");
        }
      }
      std::vector<float>& a_u_float = scratch.a_u_float;
      reserve_for_writing(a_u_float, a_u.size());
      a_u_float.assign(a_u.begin(), a_u.end());
      SimulationTrace<float>& trace = scratch.trace_float;
      reserve_trace(trace, a_u.size());
      summary = host::simulate_signal(setup, a_u_float, trace);
      host::add_ride_comfort(summary, a_u, trace.a_x_m_per_s2, dt_s);
      take_trace(output, trace, keep_trace);
    } else {
      SimulationTrace<double>& trace = scratch.trace;
      reserve_trace(trace, a_u.size());
      summary = host::simulate_signal(setup, a_u, trace);
      host::add_ride_comfort(summary, a_u, trace.a_x_m_per_s2, dt_s);
      take_trace(output, trace, keep_trace);
    }
  } catch (const ConfigurationError& error) {
    throw HostError(explain_configuration_error(error.what()));
  }
  output.stats_json = host::format_stats_json(
      summary, host::StatsContext{&setup, spec.scalar, input_label, std::string()});
  return output;
}

bool is_path(const py::handle& value) {
  return py::isinstance<py::str>(value) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

py::dict trace_dict(RunOutput& output, const py::array& t, const py::array& a_u) {
  py::dict trace;
  trace["t"] = t;
  trace["a_u"] = a_u;
  trace["x_r"] = float64_array(std::move(output.x_r));
  trace["v_r"] = float64_array(std::move(output.v_r));
  trace["a_x"] = float64_array(std::move(output.a_x));
  trace["f_f"] = float64_array(std::move(output.f_f));
  trace["stuck"] = owned_array(std::move(output.stuck), py::dtype("bool"));
  return trace;
}

py::dict stats_dict(const RunOutput& output) {
  py::dict stats = py::module_::import("json").attr("loads")(output.stats_json);
  // The core's Integrator has no 'reference': name the solver that ran (as the command does).
  if (output.reference) stats["integrator"] = "reference";
  return stats;
}

struct Recording {
  std::vector<double> t, a_u;
  std::vector<double> f_a;  // empty: no actuator force
  double dt_s = 0.0;
  std::string path;
};

// A file refuses a non-finite sample with its file:line (the command's reader); an array is
// refused the same way, by its index, rather than run with the sample rejected by the core.
void require_finite(const std::vector<double>& samples, const char* name) {
  for (std::size_t n = 0; n < samples.size(); ++n) {
    if (!std::isfinite(samples[n])) {
      throw HostError(
          std::string(name) + " = " + format_number(samples[n]) + " at sample " +
          std::to_string(n) +
          ": simulate needs finite samples (stickslip simulate refuses them in a file)");
    }
  }
}

// The samples, actuator force and dt of simulate's arguments: a file path (dt from its t column,
// f_a from its column f_a, read as the command reads it) or arrays with dt given.
Recording recording_from(const py::handle& a_u, const py::object& dt, const py::object& f_a) {
  Recording recording;
  if (is_path(a_u)) {
    recording.path = py::module_::import("os").attr("fspath")(a_u).cast<std::string>();
    if (!dt.is_none()) {
      throw HostError("dt: a recording file gives its own dt (from t); pass dt=None");
    }
    if (!f_a.is_none()) {
      throw HostError(
          "f_a: a recording file gives its own actuator force (its column f_a); "
          "pass f_a=None");
    }
    host::SampledSignal signal = read_recording_file(recording.path);
    recording.t = std::move(signal.t_s);
    recording.a_u = std::move(signal.a_u_m_per_s2);
    recording.f_a = std::move(signal.f_a_n);
    recording.dt_s = signal.dt_s;
    return recording;
  }
  if (dt.is_none()) throw HostError("dt: the sample interval (s) is required with an array");
  recording.dt_s = dt.cast<double>();
  if (!(recording.dt_s > 0.0) || !std::isfinite(recording.dt_s)) {
    throw HostError("dt: must be a finite number > 0, got " + format_number(recording.dt_s));
  }
  // t only when a trace is returned (time_line()).
  recording.a_u = samples_from(a_u, "a 1-D array of samples (m/s^2) or a file path");
  require_finite(recording.a_u, "a_u");
  if (!f_a.is_none()) {
    recording.f_a = samples_from(f_a, "a 1-D array of actuator forces (N)", "f_a");
    if (recording.f_a.size() != recording.a_u.size()) {
      throw HostError("f_a: " + std::to_string(recording.f_a.size()) + " forces for the " +
                      std::to_string(recording.a_u.size()) +
                      " samples of a_u (one per sample, held over the step that ends at it)");
    }
    require_finite(recording.f_a, "f_a");
  }
  return recording;
}

py::tuple simulate(const py::handle& a_u, const py::object& dt, const py::dict& options,
                   bool keep_trace, const py::object& f_a) {
  const RunSpec spec = parse_spec(options);
  Recording recording = recording_from(a_u, dt, f_a);
  RunOutput output;
  {
    py::gil_scoped_release release;
    Scratch scratch;
    output = run_spec(spec, recording.a_u, recording.f_a, recording.dt_s, recording.path,
                      keep_trace, scratch);
  }
  py::object trace = py::none();
  if (keep_trace) {
    if (recording.t.empty()) recording.t = time_line(recording.a_u.size(), recording.dt_s);
    trace = trace_dict(output, float64_array(std::move(recording.t)),
                       float64_array(std::move(recording.a_u)));
  }
  return py::make_tuple(trace, stats_dict(output));
}

// Many parameter sets over one recording on a pool of threads: each run is run_spec(), the same
// as a single call; the recording is shared read-only.
py::list simulate_batch(const py::handle& a_u, const py::object& dt, const py::list& params_list,
                        int threads, bool keep_trace, const py::object& f_a) {
  std::vector<RunSpec> specs;
  for (std::size_t i = 0; i < params_list.size(); ++i) {
    try {
      specs.push_back(parse_spec(params_list[i].cast<py::dict>()));
    } catch (const HostError& error) {
      throw HostError("params_list[" + std::to_string(i) + "]: " + error.what());
    } catch (const py::cast_error&) {
      throw HostError("params_list[" + std::to_string(i) + "]: expected a dict of parameters");
    }
  }
  if (threads < 0)
    throw HostError("threads: must be >= 0 (0: all cores), got " + std::to_string(threads));
  Recording recording = recording_from(a_u, dt, f_a);
  std::vector<RunOutput> outputs(specs.size());
  std::vector<std::exception_ptr> errors(specs.size());
  {
    py::gil_scoped_release release;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t workers = std::min<std::size_t>(
        threads > 0 ? static_cast<std::size_t>(threads) : cores, specs.size());
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      Scratch scratch;
      for (std::size_t i; (i = next.fetch_add(1)) < specs.size();) {
        try {
          outputs[i] = run_spec(specs[i], recording.a_u, recording.f_a, recording.dt_s,
                                recording.path, keep_trace, scratch);
        } catch (...) {
          errors[i] = std::current_exception();
        }
      }
    };
    std::vector<std::thread> pool;
    for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
    for (std::thread& thread : pool) thread.join();
  }
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (!errors[i]) continue;
    try {
      std::rethrow_exception(errors[i]);
    } catch (const HostError& error) {
      throw HostError("params_list[" + std::to_string(i) + "]: " + error.what());
    }
  }
  py::list results;
  if (specs.empty()) return results;
  if (keep_trace && recording.t.empty()) {
    recording.t = time_line(recording.a_u.size(), recording.dt_s);
  }
  const py::array t = float64_array(std::move(recording.t));
  const py::array samples = float64_array(std::move(recording.a_u));
  for (RunOutput& output : outputs) {
    py::object trace = keep_trace ? py::object(trace_dict(output, t, samples)) : py::none();
    results.append(py::make_tuple(trace, stats_dict(output)));
  }
  return results;
}

}  // namespace

void bind_runs(py::module_& m) {
  m.def("simulate", &simulate, py::arg("a_u"), py::arg("dt"), py::arg("options"),
        py::arg("trace") = true, py::arg("f_a") = py::none());
  m.def("simulate_batch", &simulate_batch, py::arg("a_u"), py::arg("dt"), py::arg("params_list"),
        py::arg("threads") = 0, py::arg("trace") = true, py::arg("f_a") = py::none());
}

}  // namespace stickslip::python
