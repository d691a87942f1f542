#include "stickslip/host/run/simulate_file.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <ostream>
#include <system_error>
#include <utility>
#include <vector>

#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/io/trace_csv.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/run/stats_json.hpp"
#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip::host {
namespace {

// The option that sets each OscillatorParams field, to point the user at what to change.
const char* option_for(const std::string& parameter) {
  static const struct {
    const char* parameter;
    const char* option;
  } table[] = {{"mass_kg", "--mass"},
               {"stiffness_n_per_m", "--stiffness"},
               {"damping_ns_per_m", "--damping"},
               {"kinetic_friction_n", "--ffk"},
               {"static_friction_n", "--ffs"},
               {"stribeck_velocity_m_per_s", "--stribeck-velocity"},
               {"smoothing_constant_s_per_m", "--smoothing-c"},
               {"model", "--model"},
               {"smoothing", "--smoothing"},
               {"input_range_m_per_s2", "--input-range"},
               {"displacement_range_m", "--displacement-range"},
               {"integrator", "--integrator"}};
  for (const auto& entry : table)
    if (parameter == entry.parameter) return entry.option;
  return nullptr;
}

// "--mass: mass_kg: must be >= 1e-06 ..." or, for the step, "IN.csv: ... dt_s: ..." (dt comes
// from t) or "--dt 2: ..." (the model's step given on the command line).
// The core's refusal as the user's mistake: the file's time step is bad data (status 1); a
// parameter the command line gave is a command-line error (status 2), one from a scene file data.
[[noreturn]] void throw_configuration_error(const std::string& core_message,
                                            const std::string& input_path, double dt_s,
                                            bool dt_given, bool from_scene) {
  const std::string parameter = core_message.substr(0, core_message.find(':'));
  if (parameter == "dt_s" && dt_given) {
    throw UsageError(
        fmt::format("--dt {}: the model's step does not suit this model: {}", dt_s, core_message));
  }
  if (parameter == "dt_s") {
    throw HostError(
        fmt::format("{}: the time step of the file (dt = {} s) does not suit this model: {}",
                    input_path, dt_s, core_message));
  }
  if (const char* option = option_for(parameter)) {
    const std::string message = std::string(option) + ": " + core_message;
    if (from_scene) throw HostError(message);
    throw UsageError(message);
  }
  throw HostError("invalid parameters: " + core_message);
}

template <typename T>
void write_trace(CsvWriter& writer, const SampledSignal& signal, const SimulationTrace<T>& trace,
                 bool header) {
  TraceCsvWriter csv(writer, header);
  const std::size_t count = signal.t_s.size();
  for (std::size_t n = 0; n < count; ++n) {
    // t and a_u echo the input exactly
    csv.row({signal.t_s[n], signal.a_u_m_per_s2[n], static_cast<double>(trace.x_r_m[n]),
             static_cast<double>(trace.v_r_m_per_s[n]), static_cast<double>(trace.a_x_m_per_s2[n]),
             static_cast<double>(trace.friction_n[n]), trace.stuck[n] != 0});
  }
  csv.flush();
}

void report(const SimulateRequest& request, const std::string& stage) {
  if (request.on_stage) request.on_stage(stage);
}

template <typename T>
SimulationSummary run_and_write(const SimulateRequest& request, const SimulationSetup& setup,
                                const SampledSignal& signal, const std::vector<T>& a_u,
                                CsvWriter& writer, bool header) {
  SimulationTrace<T> trace;
  SimulationSummary summary;
  try {
    summary = simulate_signal(setup, a_u, trace);
  } catch (const ConfigurationError& error) {
    throw_configuration_error(error.what(), request.input_path, setup.params.dt_s,
                              request.recording.dt_s > 0, !request.scene_path.empty());
  }
  add_ride_comfort(summary, signal.a_u_m_per_s2, trace.a_x_m_per_s2, setup.params.dt_s);
  report(request, "writing " + request.output_path);
  write_trace(writer, signal, trace, header);
  return summary;
}

void require_finite(const char* option, double value) {
  if (!std::isfinite(value))
    throw UsageError(fmt::format("{}: must be a finite number, got {}", option, value));
}

// The request's own consistency, before any file is read.
void check_request(const SimulateRequest& request) {
  require_finite("--x0", request.setup.x0_m);
  require_finite("--v0", request.setup.v0_m_per_s);
  if (request.setup.reference &&
      (request.scalar == ScalarType::fixed || request.scalar == ScalarType::fixed32)) {
    throw UsageError(std::string("--scalar ") + scalar_name(request.scalar) +
                     ": the reference integrator runs in double only; use --scalar double");
  }
  if (request.setup.reference && request.scalar == ScalarType::float32) {
    throw UsageError(
        "--scalar float: the reference integrator runs in double only (long double inside); "
        "use --scalar double");
  }
  if (!request.stats_path.empty()) {
    std::error_code error;
    if (request.stats_path == request.output_path ||
        std::filesystem::equivalent(request.stats_path, request.output_path, error)) {
      throw UsageError("--stats and --output name the same file: " + request.output_path);
    }
  }
}

// The loop in the request's scalar type, its trace into `writer`.
SimulationSummary run_in_scalar(const SimulateRequest& request, const SimulationSetup& setup,
                                const SampledSignal& signal, CsvWriter& writer, bool header) {
  SimulationSummary summary;
  if (request.scalar == ScalarType::fixed || request.scalar == ScalarType::fixed32) {
    SimulationTrace<double> trace;
    try {
      summary = request.scalar == ScalarType::fixed
                    ? simulate_signal_fixed(setup, signal.a_u_m_per_s2, trace)
                    : simulate_signal_fixed32(setup, signal.a_u_m_per_s2, trace);
      add_ride_comfort(summary, signal.a_u_m_per_s2, trace.a_x_m_per_s2, setup.params.dt_s);
    } catch (const ConfigurationError& error) {
      throw_configuration_error(error.what(), request.input_path, setup.params.dt_s,
                                request.recording.dt_s > 0, !request.scene_path.empty());
    }
    report(request, "writing " + request.output_path);
    write_trace(writer, signal, trace, header);
  } else if (request.scalar == ScalarType::float32) {
    // Converted once, before the loop: the float run sees only floats (and only finite ones).
    for (std::size_t n = 0; n < signal.a_u_m_per_s2.size(); ++n) {
      const double force = signal.f_a_n.empty() ? 0.0 : signal.f_a_n[n];
      if (std::fabs(force) > static_cast<double>(FLT_MAX)) {
        throw HostError(
            fmt::format("{}: f_a = {} at t = {} s is beyond the range of a float "
                        "(--scalar float)",
                        request.input_path, force, signal.t_s[n]));
      }
      if (std::fabs(signal.a_u_m_per_s2[n]) > static_cast<double>(FLT_MAX)) {
        throw HostError(
            fmt::format("{}: a_u = {} at t = {} s is beyond the range of a float "
                        "(--scalar float)",
                        request.input_path, signal.a_u_m_per_s2[n], signal.t_s[n]));
      }
    }
    const std::vector<float> a_u(signal.a_u_m_per_s2.begin(), signal.a_u_m_per_s2.end());
    summary = run_and_write(request, setup, signal, a_u, writer, header);
  } else {
    summary = run_and_write(request, setup, signal, signal.a_u_m_per_s2, writer, header);
  }
  return summary;
}

// The parts of a --gaps split run as one: RMS values weighted by samples, p by steps (each part
// starts from the initial state). Ride comfort as ISO 2631-1 combines exposures: each part's
// weighted filter starts anew, the weighted mean squares add by samples, the VDVs by their fourth
// powers (VDV is the fourth root of an integral over time), MTVV and the peak are the largest
// part's; the crest factor is that peak over the whole's weighted RMS.
SimulationSummary combine_parts(const std::vector<SimulationSummary>& parts,
                                const SimulationSetup& setup) {
  SimulationSummary all = parts.front();
  double u2 = 0.0, x2 = 0.0, stuck = 0.0;
  double floor_w2 = 0.0, seat_w2 = 0.0, vdv4 = 0.0, mtvv = 0.0, peak = 0.0;
  bool comfort = true;
  all.samples = all.steps = all.events = all.rejected_inputs = 0;
  all.event_budget_exhausted = all.state_resets = all.saturated_steps = 0;
  for (const SimulationSummary& part : parts) {
    all.samples += part.samples;
    all.steps += part.steps;
    all.events += part.events;
    all.rejected_inputs += part.rejected_inputs;
    all.event_budget_exhausted += part.event_budget_exhausted;
    all.state_resets += part.state_resets;
    all.saturated_steps += part.saturated_steps;
    u2 += static_cast<double>(part.samples) * part.rms_u * part.rms_u;
    x2 += static_cast<double>(part.samples) * part.rms_x * part.rms_x;
    stuck += static_cast<double>(part.steps) * part.stick_probability;
    comfort = comfort && part.comfort;
    floor_w2 +=
        static_cast<double>(part.samples) * part.floor_weighted_rms * part.floor_weighted_rms;
    seat_w2 += static_cast<double>(part.samples) * part.seat_weighted_rms * part.seat_weighted_rms;
    vdv4 += std::pow(part.seat_vdv, 4.0);
    mtvv = std::max(mtvv, part.seat_mtvv);
    peak = std::max(peak, part.seat_crest_factor * part.seat_weighted_rms);
  }
  all.rms_u = std::sqrt(u2 / static_cast<double>(all.samples));
  all.rms_x = std::sqrt(x2 / static_cast<double>(all.samples));
  all.transmissibility = all.rms_x / all.rms_u;
  all.stick_probability = stuck / static_cast<double>(all.steps);
  all.den_hartog_k =
      den_hartog_factor(setup.params.kinetic_friction_n, setup.params.mass_kg, all.rms_u);
  all.comfort = comfort;
  if (comfort) {
    const auto samples = static_cast<double>(all.samples);
    all.floor_weighted_rms = std::sqrt(floor_w2 / samples);
    all.seat_weighted_rms = std::sqrt(seat_w2 / samples);
    all.seat_ratio = all.seat_weighted_rms / all.floor_weighted_rms;
    all.seat_vdv = std::pow(vdv4, 0.25);
    all.seat_mtvv = mtvv;
    all.seat_crest_factor = peak / all.seat_weighted_rms;
  }
  return all;
}

// "recording": what reading did to the samples; "segments": each part of a split run.
std::string with_recording_fields(const std::string& stats_json, const LoadedRecording& recording,
                                  const std::vector<SimulationSummary>& parts) {
  auto json = nlohmann::ordered_json::parse(stats_json);
  json["recording"] = nlohmann::ordered_json::parse(recording_report_json(recording.report));
  if (parts.size() > 1) {
    auto& segments = json["segments"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < parts.size(); ++i) {
      nlohmann::ordered_json part;
      part["t_start_s"] = recording.segments[i].t_s.front();
      part["samples"] = parts[i].samples;
      part["T_ax"] = parts[i].transmissibility;
      part["p_stick"] = parts[i].stick_probability;
      segments.push_back(part);
    }
  }
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

SimulateResult simulate_file(const SimulateRequest& request) {
  check_request(request);
  report(request, "reading " + request.input_path);
  // CSV, .mat, a logger's text or a CAN log, on the model's step (recording_source.hpp).
  const LoadedRecording recording = read_recording(request.input_path, request.recording);
  const double dt_s = recording.segments.front().dt_s;
  check_scene_rate(request.input_path, request.recording, dt_s, request.scene_path,
                   request.scene_dt_s);
  SimulationSetup setup = request.setup;
  setup.params.dt_s = dt_s;
  require_force_as_read(request.input_path, recording);
  const std::vector<double>& f_a_n = recording.segments.front().f_a_n;
  if (!f_a_n.empty()) setup.actuator_force_n = &f_a_n;

  // Temporaries first: a bad output path fails before the work; any later failure removes them.
  AtomicOutputFile output(request.output_path);
  std::optional<AtomicOutputFile> stats;
  if (!request.stats_path.empty()) stats.emplace(request.stats_path);
  CsvWriter writer(output);

  SimulateResult result;
  result.recording = recording.report;
  std::size_t samples = 0;
  for (const SampledSignal& segment : recording.segments) samples += segment.a_u_m_per_s2.size();
  report(request, fmt::format("simulating {} samples", samples));
  std::vector<SimulationSummary> parts;
  for (const SampledSignal& segment : recording.segments)
    parts.push_back(run_in_scalar(request, setup, segment, writer, parts.empty()));
  result.summary = parts.size() == 1 ? parts.front() : combine_parts(parts, setup);
  result.stats_json = format_stats_json(
      result.summary,
      StatsContext{&setup, request.scalar, request.input_path, request.output_path});
  if (!request.recording.defaults()) {
    result.stats_json = with_recording_fields(result.stats_json, recording, parts);
  }
  if (setup.reference) {
    // The core's Integrator has no 'reference': name the solver that ran.
    auto json = nlohmann::ordered_json::parse(result.stats_json);
    json["integrator"] = "reference";
    result.stats_json = json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  }
  if (stats) stats->write(result.stats_json + "\n");

  commit_with_stats(output, stats ? &*stats : nullptr);
  return result;
}

}  // namespace stickslip::host
