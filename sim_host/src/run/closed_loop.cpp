#include "stickslip/host/run/closed_loop.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <system_error>

#include "stickslip/can/codec.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/gnuplot_png.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/signals/random.hpp"
#include "stickslip/metrics/ride_comfort.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::host {

namespace {

const struct {
  ControllerChoice choice;
  const char* name;
} kControllers[] = {{ControllerChoice::passive, "passive"},
                    {ControllerChoice::skyhook, "skyhook"},
                    {ControllerChoice::groundhook, "groundhook"},
                    {ControllerChoice::skyhook_semi, "skyhook-semi"},
                    {ControllerChoice::groundhook_semi, "groundhook-semi"},
                    {ControllerChoice::friction_compensation, "friction-compensation"}};

bool is_hook(ControllerChoice c) {
  return c == ControllerChoice::skyhook || c == ControllerChoice::groundhook ||
         c == ControllerChoice::skyhook_semi || c == ControllerChoice::groundhook_semi;
}

}  // namespace

const char* controller_name(ControllerChoice choice) noexcept {
  for (const auto& entry : kControllers)
    if (entry.choice == choice) return entry.name;
  return "passive";
}

bool parse_controller(const std::string& name, ControllerChoice& out) noexcept {
  for (const auto& entry : kControllers) {
    if (name == entry.name) {
      out = entry.choice;
      return true;
    }
  }
  return false;
}

std::vector<std::string> controller_names() {
  std::vector<std::string> names;
  for (const auto& entry : kControllers) names.emplace_back(entry.name);
  return names;
}

ClosedLoopParams closed_loop_params(const ClosedLoopSetup& setup, double dt_s) {
  ClosedLoopParams p;
  p.dt_s = dt_s;
  const ControllerChoice c = setup.controller;
  if (setup.user != nullptr) {
    p.controller = LoopController::user;
  } else if (is_hook(c)) {
    p.controller = LoopController::hook;
    p.hook.reference = (c == ControllerChoice::skyhook || c == ControllerChoice::skyhook_semi)
                           ? HookReference::sky
                           : HookReference::ground;
    p.hook.device = (c == ControllerChoice::skyhook || c == ControllerChoice::groundhook)
                        ? HookDevice::active
                        : HookDevice::semi_active;
    p.hook.gain_ns_per_m = setup.gain_ns_per_m;
    p.hook.min_damping_ns_per_m = setup.min_damping_ns_per_m;
    p.hook.max_damping_ns_per_m = setup.max_damping_ns_per_m;
  } else {
    p.controller = LoopController::passive;
  }
  p.friction_compensation_fraction = setup.friction_compensation;
  p.actuator.force_limit_n = setup.force_limit_n;
  p.actuator.lag_time_constant_s = setup.actuator_lag_s;
  p.observer = setup.observer;
  // The observer knows the seat the plant runs (a model-based observer's premise; its friction
  // estimates start from the scene's levels and are then learnt).
  const OscillatorParams& seat = setup.plant.params;
  p.estimator.mass_kg = seat.mass_kg;
  p.estimator.stiffness_n_per_m = seat.stiffness_n_per_m;
  p.estimator.damping_ns_per_m = seat.damping_ns_per_m;
  p.estimator.initial_kinetic_friction_n = seat.kinetic_friction_n;
  p.estimator.initial_static_friction_n = std::max(seat.static_friction_n, seat.kinetic_friction_n);
  // The filter's 4 ms low-pass and 10 ms leak are for the usual 1 ms step; a time constant
  // shorter than the step cannot act, so at a longer step they are one step (no filtering)
  // rather than a refusal of the whole loop, passive included.
  p.estimator.acceleration_filter_time_s = std::max(p.estimator.acceleration_filter_time_s, dt_s);
  p.estimator.breakaway_leak_time_s = std::max(p.estimator.breakaway_leak_time_s, dt_s);
  // The filter's belief about the sensors: what they are declared to be, where declared.
  if (setup.a_x_noise_m_per_s2 > 0.0)
    p.estimator.seat_acceleration_noise_m_per_s2 = setup.a_x_noise_m_per_s2;
  if (setup.x_r_noise_m > 0.0) p.estimator.travel_noise_m = setup.x_r_noise_m;
  p.estimator.travel_resolution_m = setup.x_r_resolution_m;
  if (!(p.estimator.travel_noise_m > 0.0 || p.estimator.travel_resolution_m > 0.0))
    p.estimator.travel_noise_m = 3e-5;
  p.seat_acceleration_resolution_m_per_s2 = setup.a_x_resolution_m_per_s2;
  p.travel_resolution_m = setup.x_r_resolution_m;
  p.floor_acceleration_resolution_m_per_s2 = setup.a_u_resolution_m_per_s2;
  p.force_resolution_n = setup.force_resolution_n;
  return p;
}

void set_can_resolution(ClosedLoopSetup& setup) {
  // Power-of-two quanta: ClosedLoop's rounding equals the codec's quantise + physical exactly.
  const auto quantum = [](const can::SignalSpec& signal) {
    return std::ldexp(1.0, -signal.fraction_bits);
  };
  setup.a_u_resolution_m_per_s2 = quantum(can::kSeatInput.signals[0]);
  setup.a_x_resolution_m_per_s2 = quantum(can::kSeatSensors.signals[0]);
  setup.x_r_resolution_m = quantum(can::kSeatSensors.signals[1]);
  setup.force_resolution_n = quantum(can::kActuatorCommand.signals[0]);
}

ControlFigures measure_control(const std::vector<double>& a_u, const SimulationTrace<double>& trace,
                               const std::vector<double>& f_a_n, double dt_s) {
  ControlFigures figures;
  const std::size_t count = a_u.size();
  // T_ax and p as simulate's loop forms them (RunningStatistics, sample by sample), so that a
  // passive loop reports simulate's figures bit for bit.
  RunningStatistics<double> statistics;
  statistics.reset();
  statistics.add_sample(a_u[0], trace.a_x_m_per_s2[0]);
  RideComfort<double> comfort;
  const ConfigResult configured = comfort.configure(ComfortWeighting::wk, 1.0 / dt_s);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  comfort.add_sample(a_u[0], trace.a_x_m_per_s2[0]);
  double travel = std::fabs(trace.x_r_m[0]);
  double force_squares = 0.0, force_peak = 0.0, work = 0.0;
  for (std::size_t n = 1; n < count; ++n) {
    statistics.add_sample(a_u[n], trace.a_x_m_per_s2[n]);
    comfort.add_sample(a_u[n], trace.a_x_m_per_s2[n]);
    travel = std::max(travel, std::fabs(trace.x_r_m[n]));
    if (!f_a_n.empty()) {
      const double f = f_a_n[n];
      force_squares += f * f;
      force_peak = std::max(force_peak, std::fabs(f));
      // The force is constant over the step: its work is exactly f * (x_r[n] - x_r[n-1]).
      work += f * (trace.x_r_m[n] - trace.x_r_m[n - 1]);
    }
  }
  // (p needs each step's stuck fraction, which the trace does not hold: the caller sets it.)
  figures.samples = statistics.samples();
  figures.transmissibility = statistics.transmissibility();
  figures.seat_weighted_rms = comfort.seat_weighted_rms();
  figures.floor_weighted_rms = comfort.floor_weighted_rms();
  figures.seat_ratio = comfort.seat_ratio();
  figures.vdv = comfort.seat_vdv();
  figures.travel_m = travel;
  const double steps = static_cast<double>(count - 1);
  figures.force_rms_n = std::sqrt(force_squares / steps);
  figures.force_peak_n = force_peak;
  figures.mean_power_w = work / (steps * dt_s);
  return figures;
}

ControlFigures run_closed_loop(const ClosedLoopSetup& setup, const std::vector<double>& a_u,
                               ClosedLoopTrace& trace) {
  const std::size_t count = a_u.size();
  if (count < 2) throw HostError("closed-loop needs at least 2 samples");
  if (setup.plant.reference) {
    throw UsageError("--integrator reference: the closed loop runs the core's integrators");
  }
  const double dt_s = setup.plant.params.dt_s;
  const ClosedLoopParams params = closed_loop_params(setup, dt_s);
  ClosedLoop<double> loop;
  ConfigResult configured = loop.configure(params);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  if (setup.user != nullptr) loop.set_user_controller(*setup.user);

  SimulationTrace<double>& plant = trace.plant;
  plant.resize(count);
  trace.f_a_n.assign(count, 0.0);
  trace.command_n.assign(count, 0.0);
  trace.sensed_v_r_m_per_s.assign(count, 0.0);
  // Independent streams for the two sensors, so that adding noise to one leaves the other's.
  GaussianSource a_x_noise(setup.seed, 1), x_r_noise(setup.seed, 2);
  // p as simulate's statistics take it: samples and steps in the same order (the block sums
  // flush on the samples), so that a passive loop's p is simulate's bit for bit.
  RunningStatistics<double> steps;
  steps.reset();
  // The plant is exactly the scene's model, as simulate chooses it (with end stops: the end-stop
  // model, whose step takes the actuator force too).
  const SceneParams scene{setup.plant.effects, setup.plant.params, setup.plant.stops};
  std::uint64_t contacts = 0;
  with_scene_model<double>(scene, [&](auto& seat) {
    configured = configure_for_scene(seat, scene);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    // No force at the start: the passive reset, as simulate's.
    seat.reset(setup.plant.x0_m, setup.plant.v0_m_per_s, a_u[0]);
    plant.store(0, seat.current());
    steps.add_sample(a_u[0], plant.a_x_m_per_s2[0]);
    loop.reset(a_u[0], setup.plant.x0_m);
    for (std::size_t n = 1; n < count; ++n) {
      const double ax_noise =
          setup.a_x_noise_m_per_s2 > 0.0 ? setup.a_x_noise_m_per_s2 * a_x_noise.next() : 0.0;
      const double xr_noise = setup.x_r_noise_m > 0.0 ? setup.x_r_noise_m * x_r_noise.next() : 0.0;
      const LoopSample<double> sample = loop.step(seat, a_u[n], ax_noise, xr_noise);
      plant.store(n, sample.plant);
      trace.f_a_n[n] = sample.applied_force_n;
      trace.command_n[n] = sample.command_n;
      trace.sensed_v_r_m_per_s[n] = sample.sensed.v_r_m_per_s;
      steps.add_sample(a_u[n], sample.plant.a_x_m_per_s2);
      steps.add_step(sample.plant.stuck_fraction);
    }
    contacts = end_stop_contacts(seat);
  });
  ControlFigures figures = measure_control(a_u, plant, trace.f_a_n, dt_s);
  figures.stick_probability = steps.stick_probability();
  figures.end_stop_contacts = contacts;
  return figures;
}

GainSweep parse_gain_sweep(const std::string& text) {
  GainSweep sweep;
  const auto bad = [&text](const char* why) {
    return UsageError(
        fmt::format("--sweep-gain {}: {} (expected LO:HI:N, e.g. 0:4000:9)", text, why));
  };
  const std::size_t first = text.find(':');
  const std::size_t second = first == std::string::npos ? first : text.find(':', first + 1);
  if (second == std::string::npos) throw bad("three fields separated by ':'");
  char* end = nullptr;
  const std::string lo = text.substr(0, first), hi = text.substr(first + 1, second - first - 1),
                    n = text.substr(second + 1);
  sweep.low_ns_per_m = std::strtod(lo.c_str(), &end);
  if (lo.empty() || *end != '\0') throw bad("LO is not a number");
  sweep.high_ns_per_m = std::strtod(hi.c_str(), &end);
  if (hi.empty() || *end != '\0') throw bad("HI is not a number");
  const long count = std::strtol(n.c_str(), &end, 10);
  if (n.empty() || *end != '\0' || count < 2 || count > 10000)
    throw bad("N must be a whole number from 2 to 10000");
  if (!std::isfinite(sweep.low_ns_per_m) || !std::isfinite(sweep.high_ns_per_m) ||
      sweep.low_ns_per_m < 0.0 || !(sweep.high_ns_per_m > sweep.low_ns_per_m))
    throw bad("need 0 <= LO < HI, finite");
  sweep.count = static_cast<int>(count);
  return sweep;
}

std::vector<double> sweep_gains(const GainSweep& sweep) {
  std::vector<double> gains;
  for (int i = 0; i < sweep.count; ++i) {
    // The endpoints exactly (no rounding of lo + (n-1) * step), so that they equal single runs.
    if (i == sweep.count - 1) {
      gains.push_back(sweep.high_ns_per_m);
    } else {
      gains.push_back(sweep.low_ns_per_m + (sweep.high_ns_per_m - sweep.low_ns_per_m) *
                                               static_cast<double>(i) /
                                               static_cast<double>(sweep.count - 1));
    }
  }
  return gains;
}

namespace {

nlohmann::ordered_json figures_json(const ControlFigures& f, bool controlled, bool end_stops) {
  nlohmann::ordered_json json;
  json["T_ax"] = f.transmissibility;
  json["p_stick"] = f.stick_probability;
  json["seat_weighted_rms"] = f.seat_weighted_rms;
  json["floor_weighted_rms"] = f.floor_weighted_rms;
  json["seat"] = f.seat_ratio;
  json["vdv"] = f.vdv;
  json["travel"] = f.travel_m;
  if (end_stops) json["end_stop_contacts"] = f.end_stop_contacts;
  if (controlled) {
    json["force_rms"] = f.force_rms_n;
    json["force_peak"] = f.force_peak_n;
    json["mean_power"] = f.mean_power_w;
  }
  return json;
}

}  // namespace

std::string control_figures_json(const ControlFigures& figures, bool controlled, bool end_stops) {
  return figures_json(figures, controlled, end_stops)
      .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

void write_loop_trace(CsvWriter& writer, const std::vector<double>& t_s,
                      const std::vector<double>& a_u, const ClosedLoopTrace& trace) {
  writer.text("t,a_u,x_r,v_r,a_x,f_f,stuck,f_a\n");
  const SimulationTrace<double>& p = trace.plant;
  for (std::size_t n = 0; n < t_s.size(); ++n) {
    writer.number(t_s[n]);
    writer.separator();
    writer.number(a_u[n]);
    writer.separator();
    writer.number(p.x_r_m[n]);
    writer.separator();
    writer.number(p.v_r_m_per_s[n]);
    writer.separator();
    writer.number(p.a_x_m_per_s2[n]);
    writer.separator();
    writer.number(p.friction_n[n]);
    writer.separator();
    writer.flag(p.stuck[n] != 0);
    writer.separator();
    writer.number(trace.f_a_n[n]);
    writer.end_row();
  }
  writer.flush();
}

namespace {

// Seat weighted RMS against actuator force RMS, one point per gain (gnuplot, PNG), written under
// a temporary name and renamed into place.
void write_pareto_plot(const std::vector<double>& gains, const std::vector<ControlFigures>& rows,
                       const ControlFigures& passive, const std::string& controller,
                       const std::string& png_path) {
  const std::string stem = fmt::format("{}.{}.tmp", png_path, static_cast<long>(getpid()));
  const std::string data_path = stem + ".dat", image_path = stem + ".png";
  {
    AtomicOutputFile data(data_path);
    std::string text;
    for (std::size_t i = 0; i < rows.size(); ++i)
      text += fmt::format("{} {} {}\n", rows[i].force_rms_n, rows[i].seat_weighted_rms, gains[i]);
    data.write(text);
    data.commit();
  }
  const std::string script = fmt::format(
      "set terminal png size 900,600; set output '{}'; set xlabel 'actuator force RMS (N)'; "
      "set ylabel 'seat weighted RMS, ISO 2631-1 Wk (m/s^2)'; set grid; "
      "set title 'stickslip closed-loop: {} gain sweep (labels: gain, Ns/m)'; "
      "plot '{}' using 1:2 with linespoints pt 7 title '{}', "
      "'' using 1:2:(sprintf('%.0f', \\$3)) with labels offset 1,1 notitle, "
      "{} with lines dt 2 title 'passive'",
      image_path, controller, data_path, controller, passive.seat_weighted_rms);
  draw_png(script, data_path, image_path, png_path, "the Pareto plot");
}

void check_request(const ClosedLoopRequest& request) {
  const ClosedLoopSetup& s = request.setup;
  if (request.sweep.count > 0 && !is_hook(s.controller)) {
    throw UsageError(
        fmt::format("--sweep-gain: sweeps the hook gain of skyhook, groundhook, skyhook-semi or "
                    "groundhook-semi; --controller {} has none",
                    controller_name(s.controller)));
  }
  if (!request.plot_path.empty() && request.sweep.count == 0)
    throw UsageError("--plot: draws the Pareto plot of a --sweep-gain run");
  if (!request.plot_path.empty() && !gnuplot_available())
    throw HostError("--plot: gnuplot is not installed (tools/install-deps.sh --report)");
  if (!request.stats_path.empty()) {
    std::error_code error;
    if (request.stats_path == request.output_path ||
        std::filesystem::equivalent(request.stats_path, request.output_path, error))
      throw UsageError("--stats and --output name the same file: " + request.output_path);
  }
}

}  // namespace

ClosedLoopResult closed_loop_file(const ClosedLoopRequest& request) {
  check_request(request);
  RecordingReport report;
  const SampledSignal signal =
      read_continuous_recording(request.input_path, request.recording, "closed-loop", &report);
  const double dt_s = signal.dt_s;
  check_scene_rate(request.input_path, request.recording, dt_s, request.scene_path,
                   request.scene_dt_s);
  if (!signal.f_a_n.empty()) {
    throw UsageError(request.input_path +
                     ": column 'f_a': closed-loop computes the actuator force itself; give it a "
                     "recording without f_a (simulate reads one)");
  }
  ClosedLoopSetup setup = request.setup;
  setup.plant.params.dt_s = dt_s;
  setup.plant.repetitions = 1;
  const std::vector<double>& a_u = signal.a_u_m_per_s2;

  AtomicOutputFile output(request.output_path);
  std::optional<AtomicOutputFile> stats;
  if (!request.stats_path.empty()) stats.emplace(request.stats_path);
  CsvWriter writer(output);

  // The passive seat: simulate's own loop (simulation.hpp), the reference the controller is
  // measured against.
  SimulationTrace<double> passive_trace;
  SimulationSummary passive_summary;
  try {
    passive_summary = simulate_signal(setup.plant, a_u, passive_trace);
  } catch (const ConfigurationError& error) {
    throw UsageError(fmt::format("invalid parameters: {}", error.what()));
  }
  ControlFigures passive = measure_control(a_u, passive_trace, {}, dt_s);
  passive.stick_probability = passive_summary.stick_probability;
  passive.end_stop_contacts = passive_summary.end_stop_contacts;
  const bool end_stops = (setup.plant.effects & kEndStops) != 0;

  nlohmann::ordered_json json;
  json["controller"] = controller_name(setup.controller);
  json["observer"] = setup.observer == ObserverKind::estimator ? "estimator" : "ideal";
  json["samples"] = passive.samples;
  json["dt"] = dt_s;
  const OscillatorParams& p = setup.plant.params;
  json["model"] = model_name(p.model);
  json["integrator"] = integrator_name(p.integrator);
  json["mass"] = p.mass_kg;
  json["stiffness"] = p.stiffness_n_per_m;
  json["damping"] = p.damping_ns_per_m;
  json["ffk"] = p.kinetic_friction_n;
  json["ffs"] = p.static_friction_n;
  json["gain"] = setup.gain_ns_per_m;
  json["b_min"] = setup.min_damping_ns_per_m;
  json["b_max"] = setup.max_damping_ns_per_m;
  json["friction_compensation"] = setup.friction_compensation;
  json["force_limit"] = setup.force_limit_n;
  json["actuator_lag"] = setup.actuator_lag_s;
  json["a_x_noise"] = setup.a_x_noise_m_per_s2;
  json["x_r_noise"] = setup.x_r_noise_m;
  json["a_x_resolution"] = setup.a_x_resolution_m_per_s2;
  json["x_r_resolution"] = setup.x_r_resolution_m;
  json["a_u_resolution"] = setup.a_u_resolution_m_per_s2;
  json["force_resolution"] = setup.force_resolution_n;
  json["seed"] = setup.seed;
  json["passive"] = figures_json(passive, false, end_stops);

  ClosedLoopResult result;
  result.recording = report;
  const auto run = [&](ClosedLoopTrace& trace) {
    try {
      return run_closed_loop(setup, a_u, trace);
    } catch (const ConfigurationError& error) {
      throw UsageError(fmt::format("invalid parameters: {}", error.what()));
    }
  };
  if (request.sweep.count == 0) {
    ClosedLoopTrace trace;
    const ControlFigures controlled = run(trace);
    json["controlled"] = figures_json(controlled, true, end_stops);
    json["seat_weighted_rms_ratio"] = controlled.seat_weighted_rms / passive.seat_weighted_rms;
    write_loop_trace(writer, signal.t_s, signal.a_u_m_per_s2, trace);
  } else {
    const std::vector<double> gains = sweep_gains(request.sweep);
    std::vector<ControlFigures> rows;
    writer.text(
        "gain,seat_weighted_rms,seat,T_ax,vdv,travel,force_rms,force_peak,mean_power,"
        "seat_weighted_rms_ratio\n");
    result.sweep_rows =
        fmt::format("{:>10} {:>12} {:>8} {:>8} {:>10} {:>10} {:>11}\n", "gain", "seat_w_rms",
                    "SEAT", "T_ax", "travel_m", "force_rms", "mean_power");
    for (const double gain : gains) {
      setup.gain_ns_per_m = gain;
      ClosedLoopTrace trace;
      const ControlFigures f = run(trace);
      rows.push_back(f);
      for (const double value : {gain, f.seat_weighted_rms, f.seat_ratio, f.transmissibility, f.vdv,
                                 f.travel_m, f.force_rms_n, f.force_peak_n, f.mean_power_w}) {
        writer.number(value);
        writer.separator();
      }
      writer.number(f.seat_weighted_rms / passive.seat_weighted_rms);
      writer.end_row();
      result.sweep_rows +=
          fmt::format("{:>10.1f} {:>12.5f} {:>8.4f} {:>8.4f} {:>10.5f} {:>10.2f} {:>11.3f}\n", gain,
                      f.seat_weighted_rms, f.seat_ratio, f.transmissibility, f.travel_m,
                      f.force_rms_n, f.mean_power_w);
    }
    writer.flush();
    json.erase("gain");
    json["sweep_gains"] = request.sweep.count;
    json["gain_low"] = request.sweep.low_ns_per_m;
    json["gain_high"] = request.sweep.high_ns_per_m;
    if (!request.plot_path.empty()) {
      write_pareto_plot(gains, rows, passive, controller_name(setup.controller), request.plot_path);
      json["plot"] = request.plot_path;
    }
  }
  json["input"] = request.input_path;
  json["output"] = request.output_path;
  result.json = json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  if (stats) stats->write(result.json + "\n");
  commit_with_stats(output, stats ? &*stats : nullptr);
  return result;
}

}  // namespace stickslip::host
