// stickslip._stickslip: the host library's simulate runner, recording readers and generators, and
// the core's oscillator and observer, for numpy arrays. The Python package (python/stickslip/)
// wraps these with keyword arguments and turns the statistics JSON into a dict.
//
// simulate runs exactly what `stickslip simulate` runs (simulate_signal*, add_ride_comfort,
// format_stats_json) on the same samples, so its trace and statistics equal the command's bit for
// bit. Arrays cross the boundary without per-sample Python work: the host's runner takes a
// std::vector, so the input is copied into one with a single memcpy; the outputs are moved into
// numpy arrays that own them (no copy). Every run releases the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "stickslip/can/codec.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/host/run/stats_json.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/models/scene.hpp"
#include "stickslip/observer/observer.hpp"

namespace py = pybind11;

namespace stickslip::python {
namespace {

using host::ConfigurationError;
using host::HostError;
using host::ScalarType;
using host::SimulationSetup;
using host::SimulationSummary;
using host::SimulationTrace;

std::string format_number(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

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

// ---------------------------------------------------------------------------------------------
// Parameters: the keyword arguments of simulate(), resolved as `stickslip simulate` resolves its
// flags (the scene file first, then every argument given over it).

struct RunSpec {
  SimulationSetup setup;
  ScalarType scalar = ScalarType::float64;
  std::string scene_path;
  double scene_dt_s = 0.0;  // 0: the scene names no sample rate
};

const char* const kOptionNames[] = {"model",
                                    "mass",
                                    "stiffness",
                                    "damping",
                                    "ffk",
                                    "ffs",
                                    "stribeck_velocity",
                                    "smoothing",
                                    "smoothing_c",
                                    "integrator",
                                    "scalar",
                                    "input_range",
                                    "displacement_range",
                                    "x0",
                                    "v0",
                                    "scene",
                                    "repetitions"};

// The argument that sets each OscillatorParams field, to point the user at what to change.
const char* argument_for(const std::string& parameter) {
  static const struct {
    const char* parameter;
    const char* argument;
  } table[] = {{"mass_kg", "mass"},
               {"stiffness_n_per_m", "stiffness"},
               {"damping_ns_per_m", "damping"},
               {"kinetic_friction_n", "ffk"},
               {"static_friction_n", "ffs"},
               {"stribeck_velocity_m_per_s", "stribeck_velocity"},
               {"smoothing_constant_s_per_m", "smoothing_c"},
               {"model", "model"},
               {"smoothing", "smoothing"},
               {"input_range_m_per_s2", "input_range"},
               {"displacement_range_m", "displacement_range"},
               {"integrator", "integrator"},
               {"dt_s", "dt"},
               {"window_s", "window_s"},
               {"exponential_time_s", "exponential_time_s"},
               {"regime_hysteresis_k", "regime_hysteresis_k"},
               {"mismatch_rms_m_per_s2", "mismatch_rms"}};
  for (const auto& entry : table)
    if (parameter == entry.parameter) return entry.argument;
  return nullptr;
}

// "mass: mass_kg: must be >= 1e-06 ..." from the core's "mass_kg: must be >= 1e-06 ...".
std::string explain_configuration_error(const std::string& core_message) {
  const std::string parameter = core_message.substr(0, core_message.find(' '));
  const std::string name = parameter.substr(0, parameter.find(':'));
  if (const char* argument = argument_for(name)) return std::string(argument) + ": " + core_message;
  return "invalid parameters: " + core_message;
}

std::optional<double> optional_number(const py::dict& options, const char* key) {
  if (!options.contains(key) || options[key].is_none()) return std::nullopt;
  try {
    return options[key].cast<double>();
  } catch (const py::cast_error&) {
    throw HostError(std::string(key) + ": expected a number, got " +
                    py::repr(options[key]).cast<std::string>());
  }
}

std::optional<std::string> optional_text(const py::dict& options, const char* key) {
  if (!options.contains(key) || options[key].is_none()) return std::nullopt;
  py::object value = options[key];
  if (std::strcmp(key, "scene") == 0) value = py::module_::import("os").attr("fspath")(value);
  if (!py::isinstance<py::str>(value)) {
    throw HostError(std::string(key) + ": expected a string, got " +
                    py::repr(value).cast<std::string>());
  }
  return value.cast<std::string>();
}

void require_finite(const char* argument, double value) {
  if (!std::isfinite(value)) {
    throw HostError(std::string(argument) + ": must be a finite number, got " +
                    format_number(value));
  }
}

RunSpec parse_spec(const py::dict& options) {
  for (const auto& item : options) {
    const std::string key = py::str(item.first);
    bool known = false;
    for (const char* name : kOptionNames) known = known || key == name;
    if (!known) {
      std::string expected;
      for (const char* name : kOptionNames)
        expected += (expected.empty() ? "" : ", ") + std::string(name);
      throw HostError("unknown parameter '" + key + "' (expected " + expected + ")");
    }
  }
  RunSpec spec;
  SimulationSetup& setup = spec.setup;
  OscillatorParams& p = setup.params;
  const std::optional<std::string> scene_path = optional_text(options, "scene");
  const bool scene = scene_path.has_value();
  if (scene) {
    const host::Scene file = host::read_scene_file(*scene_path);
    p = file.params;
    setup.effects = file.effects;
    setup.stops = file.stops;
    spec.scene_path = *scene_path;
    spec.scene_dt_s = file.sample_rate_hz ? 1.0 / *file.sample_rate_hz : 0.0;
  }
  const auto number = [&](const char* key, double& field) {
    if (const auto value = optional_number(options, key)) field = *value;
  };
  number("mass", p.mass_kg);
  number("stiffness", p.stiffness_n_per_m);
  number("damping", p.damping_ns_per_m);
  number("ffk", p.kinetic_friction_n);
  number("ffs", p.static_friction_n);
  number("stribeck_velocity", p.stribeck_velocity_m_per_s);
  number("smoothing_c", p.smoothing_constant_s_per_m);
  number("input_range", p.input_range_m_per_s2);
  number("displacement_range", p.displacement_range_m);
  const bool ffk_given = optional_number(options, "ffk").has_value();
  const bool ffs_given = optional_number(options, "ffs").has_value();
  // F_fs defaults to F_fk, unless the scene models static friction of its own.
  if (!ffs_given && (!scene || (ffk_given && !(setup.effects & kStaticFriction)))) {
    p.static_friction_n = p.kinetic_friction_n;
  }

  const std::optional<std::string> model = optional_text(options, "model");
  if (model && !parse_model(model->c_str(), p.model)) {
    throw HostError("model: unknown model '" + *model +
                    "' (expected linear, signum, smooth, stick-slip or stribeck)");
  }
  if (const auto smoothing = optional_text(options, "smoothing")) {
    if (!parse_smoothing(smoothing->c_str(), p.smoothing)) {
      throw HostError("smoothing: unknown form '" + *smoothing +
                      "' (expected atan, tanh, erf or rational)");
    }
  }
  const std::optional<std::string> integrator = optional_text(options, "integrator");
  if (!integrator) {
    // The scene's integrator stands if the scene keeps its model; else the model's default.
    if (!scene || model) p.integrator = default_integrator(p.model);
  } else if (*integrator == "reference") {
    setup.reference = true;
    p.integrator = default_integrator(p.model);
  } else if (!parse_integrator(integrator->c_str(), p.integrator)) {
    throw HostError("integrator: unknown integrator '" + *integrator +
                    "' (expected euler, symplectic, rk4, exact or reference)");
  }
  const std::string scalar = optional_text(options, "scalar").value_or("double");
  if (!host::parse_scalar(scalar, spec.scalar)) {
    throw HostError("scalar: unknown scalar '" + scalar +
                    "' (expected double, float, fixed or fixed32)");
  }
  number("x0", setup.x0_m);
  number("v0", setup.v0_m_per_s);
  require_finite("x0", setup.x0_m);
  require_finite("v0", setup.v0_m_per_s);
  // One run by default: an analyst wants the results; the command's 5 timed runs are for
  // ns_per_sample.
  setup.repetitions = 1;
  if (options.contains("repetitions") && !options["repetitions"].is_none()) {
    setup.repetitions = options["repetitions"].cast<int>();
    if (setup.repetitions < 1) {
      throw HostError("repetitions: must be >= 1, got " + std::to_string(setup.repetitions));
    }
  }
  const bool fixed = spec.scalar == ScalarType::fixed || spec.scalar == ScalarType::fixed32;
  if (setup.reference && spec.scalar != ScalarType::float64) {
    throw HostError(std::string("scalar '") + host::scalar_name(spec.scalar) +
                    "': the reference integrator runs in double only; use scalar='double'");
  }
  if ((setup.effects & kEndStops) && (setup.reference || fixed)) {
    throw HostError(
        "scene: end stops run in double or float with the core's exact integrator "
        "(not integrator='reference', not a fixed-point scalar)");
  }
  return spec;
}

// ---------------------------------------------------------------------------------------------
// One run: the host's simulate loop on samples already in memory, as simulate_file() runs it.

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

RunOutput run_spec(const RunSpec& spec, const std::vector<double>& a_u, double dt_s,
                   const std::string& input_label, bool keep_trace, Scratch& scratch) {
  if (spec.scene_dt_s > 0.0 && std::fabs(dt_s - spec.scene_dt_s) > 1e-9 * spec.scene_dt_s) {
    throw HostError("dt = " + format_number(dt_s) + " s, but the scene " + spec.scene_path +
                    " has sample_rate_hz = " + format_number(1.0 / spec.scene_dt_s) +
                    " (dt = " + format_number(spec.scene_dt_s) + " s)");
  }
  SimulationSetup setup = spec.setup;
  setup.params.dt_s = dt_s;
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
      for (std::size_t n = 0; n < a_u.size(); ++n) {
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

// ---------------------------------------------------------------------------------------------
// numpy <-> vectors.

template <typename V>
py::array owned_array(std::vector<V>&& values, py::dtype dtype) {
  auto* heap = new std::vector<V>(std::move(values));
  py::capsule owner(heap, [](void* pointer) { delete static_cast<std::vector<V>*>(pointer); });
  const py::ssize_t size = static_cast<py::ssize_t>(heap->size());
  return py::array(dtype, {size}, {static_cast<py::ssize_t>(sizeof(V))}, heap->data(), owner);
}

py::array float64_array(std::vector<double>&& values) {
  return owned_array(std::move(values), py::dtype::of<double>());
}

// Samples from any 1-D array-like; one memcpy when it is already contiguous float64.
std::vector<double> samples_from(const py::handle& a_u) {
  auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a_u);
  if (!array) throw HostError("a_u: expected a 1-D array of samples (m/s^2) or a file path");
  if (array.ndim() != 1) {
    throw HostError("a_u: expected a 1-D array of samples, got " + std::to_string(array.ndim()) +
                    " dimensions");
  }
  const std::size_t count = static_cast<std::size_t>(array.shape(0));
  std::vector<double> samples;
  reserve_for_writing(samples, count);
  samples.assign(array.data(), array.data() + count);
  return samples;
}

bool is_path(const py::handle& value) {
  return py::isinstance<py::str>(value) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

// t[n] = n dt, from the index (as the generator writes it), never accumulated.
std::vector<double> time_line(std::size_t count, double dt_s) {
  std::vector<double> t;
  reserve_for_writing(t, count);
  for (std::size_t n = 0; n < count; ++n) t.push_back(static_cast<double>(n) * dt_s);
  return t;
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
  double dt_s = 0.0;
  std::string path;
};

// The samples and dt of simulate's first two arguments: a file path (dt from its t column) or an
// array with dt given.
Recording recording_from(const py::handle& a_u, const py::object& dt) {
  Recording recording;
  if (is_path(a_u)) {
    recording.path = py::module_::import("os").attr("fspath")(a_u).cast<std::string>();
    if (!dt.is_none()) {
      throw HostError("dt: a recording file gives its own dt (from t); pass dt=None");
    }
    host::SampledSignal signal = host::read_signal_file(recording.path);
    recording.t = std::move(signal.t_s);
    recording.a_u = std::move(signal.a_u_m_per_s2);
    recording.dt_s = signal.dt_s;
    return recording;
  }
  if (dt.is_none()) throw HostError("dt: the sample interval (s) is required with an array");
  recording.dt_s = dt.cast<double>();
  if (!(recording.dt_s > 0.0) || !std::isfinite(recording.dt_s)) {
    throw HostError("dt: must be a finite number > 0, got " + format_number(recording.dt_s));
  }
  recording.a_u = samples_from(a_u);  // t only when a trace is returned (time_line())
  return recording;
}

py::tuple simulate(const py::handle& a_u, const py::object& dt, const py::dict& options,
                   bool keep_trace) {
  const RunSpec spec = parse_spec(options);
  Recording recording = recording_from(a_u, dt);
  RunOutput output;
  {
    py::gil_scoped_release release;
    Scratch scratch;
    output = run_spec(spec, recording.a_u, recording.dt_s, recording.path, keep_trace, scratch);
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
                        int threads, bool keep_trace) {
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
  Recording recording = recording_from(a_u, dt);
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
          outputs[i] = run_spec(specs[i], recording.a_u, recording.dt_s, recording.path, keep_trace,
                                scratch);
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

// ---------------------------------------------------------------------------------------------
// Readers and generators.

py::dict signal_dict(std::vector<double>&& t, std::vector<double>&& a_u, double dt_s) {
  py::dict recording;
  recording["t"] = float64_array(std::move(t));
  recording["a_u"] = float64_array(std::move(a_u));
  recording["dt"] = dt_s;
  return recording;
}

bool ends_with(const std::string& text, const char* suffix) {
  const std::size_t length = std::strlen(suffix);
  if (text.size() < length) return false;
  for (std::size_t i = 0; i < length; ++i) {
    const char c = text[text.size() - length + i];
    if ((c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c) != suffix[i]) return false;
  }
  return true;
}

// CSV (t,a_u) and .mat through the host's read_signal_file(); a candump log (.log) as the
// SeatInput frames in it (valid CRC), one sample each, t = n dt.
py::dict read_recording(const py::object& path_like, double log_dt_s) {
  const std::string path = py::module_::import("os").attr("fspath")(path_like).cast<std::string>();
  if (ends_with(path, ".log")) {
    if (!(log_dt_s > 0.0) || !std::isfinite(log_dt_s)) {
      throw HostError("dt: must be a finite number > 0, got " + format_number(log_dt_s));
    }
    const std::vector<host::LoggedFrame> frames = host::read_candump_log(path);
    std::vector<double> a_u;
    std::uint64_t skipped = 0;
    for (const host::LoggedFrame& logged : frames) {
      const can::Frame& frame = logged.frame;
      if (frame.id != can::kSeatInput.id || frame.length != can::kPayloadLength ||
          !can::crc_ok(can::kSeatInput, frame.data)) {
        ++skipped;
        continue;
      }
      const can::Payload payload = can::decode_payload(frame.data);
      a_u.push_back(can::physical<double>(can::kSeatInput.signals[0], payload.words[0]));
    }
    if (a_u.size() < 2) throw HostError(path + ": fewer than 2 SeatInput frames");
    std::vector<double> t = time_line(a_u.size(), log_dt_s);
    py::dict recording = signal_dict(std::move(t), std::move(a_u), log_dt_s);
    recording["skipped_frames"] = skipped;
    return recording;
  }
  host::SampledSignal signal = host::read_signal_file(path);
  return signal_dict(std::move(signal.t_s), std::move(signal.a_u_m_per_s2), signal.dt_s);
}

py::dict generate(const std::string& kind, std::optional<double> rms, double duration_s,
                  double dt_s, std::uint64_t seed, double frequency_hz, double band_low_hz,
                  double band_high_hz) {
  std::vector<double> a_u;
  host::SpectrumSignalSpec spectrum;
  const host::TargetSpectrum* table = host::find_seat_test_spectrum(kind);
  if (table != nullptr || kind == "white") {
    if (table != nullptr) {
      spectrum.spectrum = *table;
    } else {
      if (!rms) throw HostError("rms: required for white");
      if (!std::isfinite(band_low_hz) || !(band_low_hz >= 0.0) || !std::isfinite(band_high_hz) ||
          !(band_high_hz > band_low_hz)) {
        throw HostError("band_low/band_high: need 0 <= low < high, got " +
                        format_number(band_low_hz) + " and " + format_number(band_high_hz));
      }
      spectrum.spectrum = host::white_noise_spectrum(band_low_hz, band_high_hz, 1.0);
    }
    spectrum.rms_m_per_s2 = rms.value_or(0.0);
    if (rms && !(*rms > 0.0))
      throw HostError("rms: must be a finite number > 0, got " + format_number(*rms));
    spectrum.duration_s = duration_s;
    spectrum.dt_s = dt_s;
    spectrum.seed = seed;
    host::validate(spectrum);
    py::gil_scoped_release release;
    a_u = host::generate_spectrum_signal(spectrum);
  } else {
    host::GeneratorSpec spec;
    if (!host::parse_signal_kind(kind, spec.kind)) {
      throw HostError("kind: unknown kind '" + kind +
                      "' (expected wideband, lorry, harmonic, white, EM1..EM9, IT1, IT4, AG2 or "
                      "AG3)");
    }
    if (!rms) throw HostError("rms: required for " + kind);
    spec.rms_m_per_s2 = *rms;
    spec.duration_s = duration_s;
    spec.dt_s = dt_s;
    spec.seed = seed;
    spec.frequency_hz = frequency_hz;
    host::validate(spec);
    py::gil_scoped_release release;
    a_u = host::generate_signal(spec);
  }
  std::vector<double> t = time_line(a_u.size(), dt_s);
  return signal_dict(std::move(t), std::move(a_u), dt_s);
}

// ---------------------------------------------------------------------------------------------
// The core's oscillator, sample by sample: the model type the scene names, chosen once.

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

class AnySeat {
 public:
  virtual ~AnySeat() = default;
  virtual void reset(double x0_m, double v0_m_per_s, double a_u0) = 0;
  virtual Sample step(double a_u) = 0;
  virtual Sample current() const = 0;
  // step() for every sample of a_u, the outputs into the arrays (n samples each).
  virtual void run(const double* a_u, std::size_t n, double* x_r, double* v_r, double* a_x,
                   double* f_f, std::uint8_t* stuck) = 0;
  virtual std::uint64_t rejected_inputs() const = 0;
  virtual std::uint64_t event_budget_exhausted() const = 0;
  virtual std::uint64_t state_resets() const = 0;
};

template <typename T, typename Model>
class SeatOf final : public AnySeat {
 public:
  Model model;
  void reset(double x0_m, double v0_m_per_s, double a_u0) override {
    model.reset(static_cast<T>(x0_m), static_cast<T>(v0_m_per_s), static_cast<T>(a_u0));
  }
  Sample step(double a_u) override { return sample_of(model.step(static_cast<T>(a_u))); }
  Sample current() const override { return sample_of(model.current()); }
  void run(const double* a_u, std::size_t n, double* x_r, double* v_r, double* a_x, double* f_f,
           std::uint8_t* stuck) override {
    for (std::size_t i = 0; i < n; ++i) {
      const StepOutput<T> out = model.step(static_cast<T>(a_u[i]));
      x_r[i] = static_cast<double>(out.x_r_m);
      v_r[i] = static_cast<double>(out.v_r_m_per_s);
      a_x[i] = static_cast<double>(out.a_x_m_per_s2);
      f_f[i] = static_cast<double>(out.friction_n);
      stuck[i] = out.stuck ? 1 : 0;
    }
  }
  std::uint64_t rejected_inputs() const override { return model.rejected_inputs(); }
  std::uint64_t event_budget_exhausted() const override { return model.event_budget_exhausted(); }
  std::uint64_t state_resets() const override { return model.state_resets(); }
};

template <typename T>
std::unique_ptr<AnySeat> make_seat(const SceneParams& scene) {
  std::unique_ptr<AnySeat> seat;
  with_scene_model<T>(scene, [&](auto& prototype) {
    using Model = std::decay_t<decltype(prototype)>;
    auto made = std::make_unique<SeatOf<T, Model>>();
    const ConfigResult configured = configure_for_scene(made->model, scene);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    seat = std::move(made);
  });
  return seat;
}

class PyOscillator {
 public:
  PyOscillator(double dt_s, const py::dict& options) : spec_(parse_spec(options)) {
    if (spec_.setup.reference) {
      throw HostError("integrator: 'reference' is the host's whole-signal solver; use simulate()");
    }
    if (spec_.scalar != ScalarType::float64 && spec_.scalar != ScalarType::float32) {
      throw HostError(std::string("scalar: Oscillator runs 'double' or 'float', not '") +
                      host::scalar_name(spec_.scalar) + "'; use simulate() for fixed point");
    }
    spec_.setup.params.dt_s = dt_s;
    const SceneParams scene{spec_.setup.effects, spec_.setup.params, spec_.setup.stops};
    try {
      seat_ =
          spec_.scalar == ScalarType::float32 ? make_seat<float>(scene) : make_seat<double>(scene);
    } catch (const ConfigurationError& error) {
      throw HostError(explain_configuration_error(error.what()));
    }
    seat_->reset(spec_.setup.x0_m, spec_.setup.v0_m_per_s, 0.0);
  }

  void reset(double x0_m, double v0_m_per_s, double a_u0) { seat_->reset(x0_m, v0_m_per_s, a_u0); }
  Sample step(double a_u) { return seat_->step(a_u); }
  Sample current() const { return seat_->current(); }

  // Steps over a whole array: the input read in place (contiguous float64; other arrays are
  // converted once), the outputs written straight into new numpy arrays, the GIL released.
  py::dict run(const py::array_t<double, py::array::c_style | py::array::forcecast>& a_u) {
    if (a_u.ndim() != 1) throw HostError("a_u: expected a 1-D array of samples");
    const py::ssize_t n = a_u.shape(0);
    py::array_t<double> x_r(n), v_r(n), a_x(n), f_f(n);
    py::array_t<bool> stuck(n);
    static_assert(sizeof(bool) == sizeof(std::uint8_t), "numpy's bool is one byte");
    {
      py::gil_scoped_release release;
      seat_->run(a_u.data(), static_cast<std::size_t>(n), x_r.mutable_data(), v_r.mutable_data(),
                 a_x.mutable_data(), f_f.mutable_data(),
                 reinterpret_cast<std::uint8_t*>(stuck.mutable_data()));
    }
    py::dict trace;
    trace["x_r"] = x_r;
    trace["v_r"] = v_r;
    trace["a_x"] = a_x;
    trace["f_f"] = f_f;
    trace["stuck"] = stuck;
    return trace;
  }

  const RunSpec& spec() const { return spec_; }
  const AnySeat& seat() const { return *seat_; }

 private:
  RunSpec spec_;
  std::unique_ptr<AnySeat> seat_;
};

// ---------------------------------------------------------------------------------------------
// The observer (double), for the friction law the parameters name.

struct Estimate {
  Sample model;
  bool measured = false;
  double residual = 0.0, measured_friction = 0.0;
};

class AnyObserver {
 public:
  virtual ~AnyObserver() = default;
  virtual void reset(double a_u0, double x0_m, double v0_m_per_s) = 0;
  virtual Estimate update(double a_u) = 0;
  virtual Estimate update(double a_u, double a_x_measured) = 0;
  virtual ObserverSummary summary() const = 0;
  virtual std::uint64_t samples() const = 0;
  virtual double seat_weighted_rms() const = 0;
  virtual double seat_vdv() const = 0;
};

template <typename Law>
class ObserverOf final : public AnyObserver {
 public:
  Observer<double, Law> observer;
  void reset(double a_u0, double x0_m, double v0_m_per_s) override {
    observer.reset(a_u0, x0_m, v0_m_per_s);
  }
  Estimate update(double a_u) override { return estimate_of(observer.update(a_u)); }
  Estimate update(double a_u, double a_x_measured) override {
    return estimate_of(observer.update(a_u, a_x_measured));
  }
  ObserverSummary summary() const override { return observer.summary(); }
  std::uint64_t samples() const override { return observer.samples(); }
  double seat_weighted_rms() const override { return observer.comfort().seat_weighted_rms(); }
  double seat_vdv() const override { return observer.comfort().seat_vdv(); }

 private:
  static Estimate estimate_of(const ObserverEstimate<double>& e) {
    return {sample_of(e.model), e.measured, e.residual_m_per_s2, e.measured_friction_n};
  }
};

class PyObserver {
 public:
  PyObserver(double dt_s, const py::dict& options, double window_s, double exponential_time_s,
             double regime_hysteresis_k, double mismatch_rms) {
    const RunSpec spec = parse_spec(options);
    if (spec.scalar != ScalarType::float64 || spec.setup.reference ||
        (spec.setup.effects & kEndStops)) {
      throw HostError(
          "Observer runs the core's oscillator in double, without end stops or the reference "
          "solver");
    }
    ObserverParams params;
    params.model = spec.setup.params;
    params.model.dt_s = dt_s;
    params.window_s = window_s;
    params.exponential_time_s = exponential_time_s;
    params.regime_hysteresis_k = regime_hysteresis_k;
    params.mismatch_rms_m_per_s2 = mismatch_rms;
    with_oscillator<double>(params.model, [&](auto& prototype) {
      using Law = typename std::decay_t<decltype(prototype)>::FrictionLaw;
      auto made = std::make_unique<ObserverOf<Law>>();
      const ConfigResult configured = made->observer.configure(params);
      if (!configured.ok())
        throw HostError(explain_configuration_error(configured.message.c_str()));
      observer_ = std::move(made);
    });
    observer_->reset(0.0, spec.setup.x0_m, spec.setup.v0_m_per_s);
  }
  AnyObserver& get() { return *observer_; }
  const AnyObserver& get() const { return *observer_; }

 private:
  std::unique_ptr<AnyObserver> observer_;
};

py::dict summary_dict(const AnyObserver& observer) {
  const ObserverSummary s = observer.summary();
  py::dict d;
  d["samples"] = observer.samples();
  d["rms_u"] = s.rms_u_m_per_s2;
  d["rms_x"] = s.rms_x_m_per_s2;
  d["T_ax"] = s.transmissibility;
  d["p_stick"] = s.stick_probability;
  d["K"] = s.den_hartog_k;
  d["stick_events"] = s.stick_events;
  d["slip_events"] = s.slip_events;
  d["window_s"] = s.window_s;
  d["window_full"] = s.window_full;
  d["exp_rms_u"] = s.exp_rms_u_m_per_s2;
  d["exp_rms_x"] = s.exp_rms_x_m_per_s2;
  d["exp_T_ax"] = s.exp_transmissibility;
  d["exp_p_stick"] = s.exp_stick_probability;
  d["exp_K"] = s.exp_den_hartog_k;
  d["regime"] = s.regime_known ? py::object(py::str(regime_name(s.regime))) : py::none();
  d["regime_changes"] = s.regime_changes;
  d["residual_rms"] = s.residual_rms_m_per_s2;
  d["model_mismatch"] = s.model_mismatch;
  d["seat_weighted_rms"] = observer.seat_weighted_rms();
  d["vdv"] = observer.seat_vdv();
  return d;
}

}  // namespace
}  // namespace stickslip::python

PYBIND11_MODULE(_stickslip, m) {
  using namespace stickslip::python;
  namespace host = stickslip::host;
  m.doc() = "stickslip's C++ core and host library (use the stickslip package)";

  // Every bad argument or bad file is a HostError with a complete one-line message.
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const host::HostError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  m.def("simulate", &simulate, py::arg("a_u"), py::arg("dt"), py::arg("options"),
        py::arg("trace") = true);
  m.def("simulate_batch", &simulate_batch, py::arg("a_u"), py::arg("dt"), py::arg("params_list"),
        py::arg("threads") = 0, py::arg("trace") = true);
  m.def("read_recording", &read_recording, py::arg("path"), py::arg("dt") = 1e-3);
  m.def("generate", &generate, py::arg("kind"), py::arg("rms"), py::arg("duration"), py::arg("dt"),
        py::arg("seed") = 1, py::arg("frequency") = 0.0, py::arg("band_low") = 0.5,
        py::arg("band_high") = 20.0);
  m.def("den_hartog_factor", &stickslip::den_hartog_factor, py::arg("ffk"), py::arg("mass"),
        py::arg("rms_u"));

  py::class_<Sample>(m, "Step", "One step's output (SI units)")
      .def_readonly("x_r", &Sample::x_r)
      .def_readonly("v_r", &Sample::v_r)
      .def_readonly("a_x", &Sample::a_x)
      .def_readonly("f_f", &Sample::f_f)
      .def_readonly("stuck", &Sample::stuck)
      .def_readonly("stuck_time", &Sample::stuck_time)
      .def_readonly("stuck_fraction", &Sample::stuck_fraction)
      .def_readonly("events", &Sample::events)
      .def("__repr__", [](const Sample& s) {
        return "Step(x_r=" + format_number(s.x_r) + ", v_r=" + format_number(s.v_r) +
               ", a_x=" + format_number(s.a_x) + ", f_f=" + format_number(s.f_f) +
               ", stuck=" + (s.stuck ? "True" : "False") + ")";
      });

  py::class_<PyOscillator>(m, "Oscillator")
      .def(py::init<double, const py::dict&>(), py::arg("dt"), py::arg("options"))
      .def("reset", &PyOscillator::reset, py::arg("x0") = 0.0, py::arg("v0") = 0.0,
           py::arg("a_u0") = 0.0)
      .def("step", &PyOscillator::step, py::arg("a_u"))
      .def("current", &PyOscillator::current)
      .def("run", &PyOscillator::run, py::arg("a_u"))
      .def_property_readonly("dt", [](const PyOscillator& o) { return o.spec().setup.params.dt_s; })
      .def_property_readonly(
          "model",
          [](const PyOscillator& o) { return stickslip::model_name(o.spec().setup.params.model); })
      .def_property_readonly("integrator",
                             [](const PyOscillator& o) {
                               return stickslip::integrator_name(o.spec().setup.params.integrator);
                             })
      .def_property_readonly(
          "scalar", [](const PyOscillator& o) { return host::scalar_name(o.spec().scalar); })
      .def_property_readonly("rejected_inputs",
                             [](const PyOscillator& o) { return o.seat().rejected_inputs(); })
      .def_property_readonly(
          "event_budget_exhausted",
          [](const PyOscillator& o) { return o.seat().event_budget_exhausted(); })
      .def_property_readonly("state_resets",
                             [](const PyOscillator& o) { return o.seat().state_resets(); });

  py::class_<Estimate>(m, "Estimate", "One observer update")
      .def_readonly("model", &Estimate::model)
      .def_readonly("measured", &Estimate::measured)
      .def_readonly("residual", &Estimate::residual)
      .def_readonly("measured_friction", &Estimate::measured_friction);

  py::class_<PyObserver>(m, "Observer")
      .def(py::init<double, const py::dict&, double, double, double, double>(), py::arg("dt"),
           py::arg("options"), py::arg("window_s") = 10.0, py::arg("exponential_time_s") = 10.0,
           py::arg("regime_hysteresis_k") = 0.05, py::arg("mismatch_rms") = 0.1)
      .def(
          "reset",
          [](PyObserver& o, double a_u0, double x0, double v0) { o.get().reset(a_u0, x0, v0); },
          py::arg("a_u0") = 0.0, py::arg("x0") = 0.0, py::arg("v0") = 0.0)
      .def(
          "update",
          [](PyObserver& o, double a_u, std::optional<double> a_x_measured) {
            return a_x_measured ? o.get().update(a_u, *a_x_measured) : o.get().update(a_u);
          },
          py::arg("a_u"), py::arg("a_x_measured") = py::none())
      .def("summary", [](const PyObserver& o) { return summary_dict(o.get()); });
}
