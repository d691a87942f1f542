#include "stickslip/host/bus/control_nodes.hpp"

#include <fmt/format.h>
#include <time.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "bus_endpoint.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/host/signals/random.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::host {

namespace {

using Clock = std::chrono::steady_clock;

std::string dump(const nlohmann::ordered_json& json) {
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::int64_t monotonic_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

// Sleeps until the absolute CLOCK_MONOTONIC time (ns); returns the wake-up time.
std::int64_t sleep_until_ns(std::int64_t deadline_ns) {
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(deadline_ns / 1000000000);
  deadline.tv_nsec = static_cast<long>(deadline_ns % 1000000000);
  // EINTR (a signal): sleep again to the same absolute deadline.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) != 0) {
  }
  return monotonic_ns();
}

int milliseconds_until(Clock::time_point until) {
  const auto left = std::chrono::duration_cast<std::chrono::microseconds>(until - Clock::now());
  if (left.count() <= 0) return 0;
  return static_cast<int>((left.count() + 999) / 1000);  // round up: never wake before `until`
}

// The answer to one sample as the plant received it.
struct Answer {
  bool received = false;
  bool passive = false;
  double force_n = 0.0;
};

PacingReport pacing_report(std::vector<double> lateness_s, double dt_s) {
  PacingReport report;
  report.ticks = lateness_s.size();
  if (lateness_s.empty()) return report;
  for (const double late : lateness_s)
    if (late >= dt_s) ++report.deadline_misses;
  std::sort(lateness_s.begin(), lateness_s.end());
  const std::size_t count = lateness_s.size();
  report.lateness_median_s = lateness_s[count / 2];
  // The smallest value with at least 99.9 % of the ticks at or below it.
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.999 * static_cast<double>(count)));
  report.lateness_p999_s = lateness_s[std::max<std::size_t>(rank, 1) - 1];
  report.lateness_worst_s = lateness_s.back();
  return report;
}

// The plant's JSON line (its keys: sim_host/README.md, checked by tests/docs/run_blocks.py).
std::string plant_json(const PlantNodeRequest& request, const PlantNodeResult& r,
                       std::size_t count) {
  nlohmann::ordered_json json;
  json["node"] = "plant";
  json["bus"] = request.bus;
  json["pace"] = request.pace == Pace::realtime ? "realtime" : "max";
  json["samples"] = count;
  json["dt"] = r.dt_s;
  json["hold_frames"] = request.hold_frames;
  json["command_timeout"] = request.command_timeout_s;
  json["state"] = r.state;
  json["commands_applied"] = r.counters.commands_applied;
  json["commands_passive"] = r.counters.commands_passive;
  json["commands_missing"] = r.counters.commands_missing;
  json["commands_late"] = r.counters.commands_late;
  json["commands_corrupt"] = r.counters.commands_corrupt;
  json["held_frames"] = r.counters.held_frames;
  json["failsafe_frames"] = r.counters.failsafe_frames;
  json["bus_down_frames"] = r.counters.bus_down_frames;
  json["first_failsafe_sample"] = r.counters.first_failsafe_sample;
  json["last_failsafe_sample"] = r.counters.last_failsafe_sample;
  json["bus_down_sample"] = r.counters.bus_down_sample;
  json["controlled"] = nlohmann::ordered_json::parse(
      control_figures_json(r.figures, true, (request.setup.plant.effects & kEndStops) != 0));
  if (request.pace == Pace::realtime) {
    nlohmann::ordered_json pacing;
    pacing["ticks"] = r.pacing.ticks;
    pacing["deadline_misses"] = r.pacing.deadline_misses;
    pacing["lateness_median"] = r.pacing.lateness_median_s;
    pacing["lateness_p999"] = r.pacing.lateness_p999_s;
    pacing["lateness_worst"] = r.pacing.lateness_worst_s;
    json["pacing"] = pacing;
  }
  json["input"] = request.input_path;
  json["output"] = request.output_path;
  return dump(json);
}

// The controller's JSON line (its keys: sim_host/README.md, checked by tests/docs/run_blocks.py).
std::string controller_json(const ControllerNodeRequest& request, const ClosedLoopSetup& setup,
                            const ControllerNodeResult& r) {
  nlohmann::ordered_json json;
  json["node"] = "controller";
  json["bus"] = request.bus;
  json["controller"] = controller_name(setup.controller);
  json["dt"] = setup.plant.params.dt_s;
  json["samples"] = r.samples;
  json["answered"] = r.answered;
  json["dropped"] = r.dropped;
  json["silenced"] = r.silenced;
  json["corrupt_frames"] = r.corrupt_frames;
  json["sample_gaps"] = r.sample_gaps;
  json["restarts"] = r.restarts;
  json["send_failures"] = r.send_failures;
  json["state"] = r.bus_error.empty() ? "ok" : "bus_down";
  return dump(json);
}

}  // namespace

PlantNodeResult run_plant_node(const PlantNodeRequest& request) {
  if (request.hold_frames < 0)
    throw UsageError(fmt::format("--hold-frames: must be >= 0, got {}", request.hold_frames));
  if (!(request.command_timeout_s > 0.0 && std::isfinite(request.command_timeout_s)))
    throw UsageError(
        fmt::format("--command-timeout: must be > 0 s, got {}", request.command_timeout_s));
  if (!(request.connect_timeout_s > 0.0 && std::isfinite(request.connect_timeout_s)))
    throw UsageError(
        fmt::format("--connect-timeout: must be > 0 s, got {}", request.connect_timeout_s));
  PlantNodeResult result;
  const SampledSignal signal =
      read_continuous_recording(request.input_path, request.recording, "plant", &result.recording);
  const double dt_s = signal.dt_s;
  result.dt_s = dt_s;
  check_scene_rate(request.input_path, request.recording, dt_s, request.scene_path,
                   request.scene_dt_s);
  if (!signal.f_a_n.empty()) {
    throw UsageError(request.input_path +
                     ": column 'f_a': the plant takes the actuator force from the controller; "
                     "give it a recording without f_a");
  }
  const std::vector<double>& a_u = signal.a_u_m_per_s2;
  const std::size_t count = a_u.size();
  if (count < 2) throw HostError(request.input_path + ": the plant needs at least 2 samples");
  ClosedLoopSetup setup = request.setup;
  set_can_resolution(setup);
  setup.plant.params.dt_s = dt_s;
  LoopSensors<double> sensors;
  ConfigResult configured = sensors.configure(closed_loop_params(setup, dt_s));
  if (!configured.ok())
    throw UsageError(fmt::format("invalid parameters: {}", configured.message.c_str()));

  std::unique_ptr<port::Transport> owned;
  port::Transport* bus = request.transport;
  if (bus == nullptr) {
    owned = open_bus(request.bus, "--bus");
    bus = owned.get();
  }
  const port::ReceiveFilter filter{can::kActuatorCommand.id, 0x7FFu};
  bus->set_filters(&filter, 1);

  AtomicOutputFile output(request.output_path);
  std::optional<AtomicOutputFile> stats;
  if (!request.stats_path.empty()) stats.emplace(request.stats_path);

  ClosedLoopTrace trace;
  SimulationTrace<double>& plant = trace.plant;
  plant.resize(count);
  trace.f_a_n.assign(count, 0.0);
  // The streams closed-loop draws, so that the noisy sensors are the same samples.
  GaussianSource a_x_noise(setup.seed, 1), x_r_noise(setup.seed, 2);
  RunningStatistics<double> steps;
  steps.reset();

  PlantCounters& counters = result.counters;
  bool bus_down = false;
  const auto mark_bus_down = [&](std::uint64_t n, port::TransportStatus status) {
    if (bus_down) return;
    bus_down = true;
    counters.bus_down_sample = n;
    result.bus_message =
        fmt::format("plant: the bus {} failed at sample {} ({}): passive (f_a = 0) from here on",
                    request.bus, n, port::transport_status_name(status));
  };
  const auto send_sample = [&](std::uint64_t n, double a_u_n, double a_x_n, double x_r_n) {
    if (bus_down) return;
    for (const can::Frame& frame :
         {can::make_sensor_frame(a_x_n, x_r_n, n), can::make_input_frame(a_u_n, n)}) {
      const port::TransportStatus status = send_frame(*bus, frame);
      if (status != port::TransportStatus::ok) {
        mark_bus_down(n, status);
        return;
      }
    }
  };
  // Reads answers until the one to sample n or `until`; others are late (ignored).
  const auto await_answer = [&](std::uint64_t n, Clock::time_point until) {
    Answer answer;
    const std::uint16_t wanted = static_cast<std::uint16_t>(n & 0xFFFFu);
    while (!bus_down) {
      can::Frame frame;
      const port::TransportStatus status = bus->receive(frame, milliseconds_until(until));
      if (status == port::TransportStatus::timeout) break;
      if (status != port::TransportStatus::ok) {
        mark_bus_down(n, status);
        break;
      }
      if (frame.id != can::kActuatorCommand.id) continue;
      if (frame.length != can::kPayloadLength || !can::crc_ok(can::kActuatorCommand, frame.data)) {
        ++counters.commands_corrupt;
        continue;
      }
      const can::Payload payload = can::decode_payload(frame.data);
      if (payload.sample_counter != wanted) {
        ++counters.commands_late;
        continue;
      }
      const double force =
          can::physical<double>(can::kActuatorCommand.signals[0], payload.words[0]);
      answer.received = true;
      answer.passive = (payload.flags & can::kCommandPassive) != 0 || std::isnan(force);
      answer.force_n = answer.passive ? 0.0 : force;
      break;
    }
    return answer;
  };
  // The force over step n -> n+1 from the answer to sample n (the fault policy).
  double last_force_n = 0.0;
  int missing_run = 0;
  const auto decide = [&](std::uint64_t n, const Answer& answer) {
    if (bus_down) {
      ++counters.bus_down_frames;
      return 0.0;
    }
    if (answer.received) {
      missing_run = 0;
      ++counters.commands_applied;
      if (answer.passive) ++counters.commands_passive;
      last_force_n = answer.force_n;
      return answer.force_n;
    }
    ++counters.commands_missing;
    if (missing_run < request.hold_frames) {
      ++missing_run;
      ++counters.held_frames;
      return last_force_n;
    }
    if (missing_run == request.hold_frames) {
      counters.last_failsafe_sample = n;
      if (counters.first_failsafe_sample == 0) counters.first_failsafe_sample = n;
    }
    missing_run = request.hold_frames + 1;
    ++counters.failsafe_frames;
    return 0.0;
  };

  std::vector<double> lateness_s;
  const bool realtime = request.pace == Pace::realtime;
  if (realtime) lateness_s.reserve(count);
  const auto timeout = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(request.command_timeout_s));
  // Failing safe, the plant no longer waits the full timeout for each answer, one period only.
  const auto failsafe_wait = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(std::max(dt_s, 1e-3)));

  // The plant is the scene's model, as closed-loop's (with end stops: the end-stop model).
  const SceneParams scene{setup.plant.effects, setup.plant.params, setup.plant.stops};
  std::uint64_t contacts = 0;
  with_scene_model<double>(scene, [&](auto& seat) {
    configured = configure_for_scene(seat, scene);
    if (!configured.ok())
      throw UsageError(fmt::format("invalid parameters: {}", configured.message.c_str()));
    seat.reset(setup.plant.x0_m, setup.plant.v0_m_per_s, a_u[0]);
    plant.store(0, seat.current());
    steps.add_sample(a_u[0], plant.a_x_m_per_s2[0]);
    // Sample 0 is the greeting: re-sent every 100 ms until the controller answers it.
    const Clock::time_point connect_deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(request.connect_timeout_s));
    Answer first;
    while (!first.received && !bus_down && Clock::now() < connect_deadline) {
      send_sample(0, a_u[0], sensors.a_x(plant.a_x_m_per_s2[0], 0.0),
                  sensors.x_r(plant.x_r_m[0], 0.0));
      first = await_answer(
          0, std::min(Clock::now() + std::chrono::milliseconds(100), connect_deadline));
    }
    if (!first.received && !bus_down) {
      throw HostError(fmt::format(
          "--bus {}: no controller answered sample 0 within {} s (start `stickslip controller "
          "--bus {}` first)",
          request.bus, request.connect_timeout_s, request.bus));
    }
    double force_n = decide(0, first);
    const std::int64_t start_ns = monotonic_ns();
    for (std::size_t n = 1; n < count; ++n) {
      if (realtime) {
        const std::int64_t deadline_ns =
            start_ns + static_cast<std::int64_t>(std::llround(static_cast<double>(n) * dt_s * 1e9));
        lateness_s.push_back(static_cast<double>(sleep_until_ns(deadline_ns) - deadline_ns) * 1e-9);
        // The answer to the previous sample, if it came within the period.
        if (n >= 2) force_n = decide(n - 1, await_answer(n - 1, Clock::now()));
      }
      const StepOutput<double> out = seat.step(a_u[n], force_n);
      plant.store(n, out);
      trace.f_a_n[n] = force_n;
      steps.add_sample(a_u[n], out.a_x_m_per_s2);
      steps.add_step(out.stuck_fraction);
      const double ax_noise =
          setup.a_x_noise_m_per_s2 > 0.0 ? setup.a_x_noise_m_per_s2 * a_x_noise.next() : 0.0;
      const double xr_noise = setup.x_r_noise_m > 0.0 ? setup.x_r_noise_m * x_r_noise.next() : 0.0;
      send_sample(n, a_u[n], sensors.a_x(out.a_x_m_per_s2, ax_noise),
                  sensors.x_r(out.x_r_m, xr_noise));
      // Lock-step: the answer to this sample before the next step (none needed after the last).
      if (!realtime && n + 1 < count) {
        const bool failing_safe = missing_run > request.hold_frames;
        force_n =
            decide(n, await_answer(n, Clock::now() + (failing_safe ? failsafe_wait : timeout)));
      }
    }
    contacts = end_stop_contacts(seat);
  });
  result.figures = measure_control(a_u, plant, trace.f_a_n, dt_s);
  result.figures.stick_probability = steps.stick_probability();
  result.figures.end_stop_contacts = contacts;
  result.pacing = pacing_report(std::move(lateness_s), dt_s);
  result.state = bus_down ? "bus_down" : (missing_run > request.hold_frames ? "failsafe" : "ok");

  result.json = plant_json(request, result, count);

  CsvWriter writer(output);
  write_loop_trace(writer, signal.t_s, a_u, trace);
  if (stats) stats->write(result.json + "\n");
  commit_with_stats(output, stats ? &*stats : nullptr);
  return result;
}

ControllerNodeResult run_controller_node(const ControllerNodeRequest& request) {
  ClosedLoopSetup setup = request.setup;
  if (setup.observer == ObserverKind::ideal) {
    throw UsageError(
        "--observer ideal: over a bus the controller has only the frames' sensors; use the "
        "estimator");
  }
  const double force_range_n = std::ldexp(static_cast<double>(can::kSignedMax),
                                          -can::kActuatorCommand.signals[0].fraction_bits);
  if (setup.force_limit_n > force_range_n) {
    throw UsageError(fmt::format("--force-limit {}: the ActuatorCommand frame carries at most {} N",
                                 setup.force_limit_n, force_range_n));
  }
  if (!(request.idle_exit_s > 0.0 && std::isfinite(request.idle_exit_s)))
    throw UsageError(fmt::format("--idle-exit: must be > 0 s, got {}", request.idle_exit_s));
  set_can_resolution(setup);
  const double dt_s = setup.plant.params.dt_s;
  ControlUnit<double> unit;
  const ConfigResult configured = unit.configure(closed_loop_params(setup, dt_s));
  if (!configured.ok())
    throw UsageError(fmt::format("invalid parameters: {}", configured.message.c_str()));
  if (setup.user != nullptr) unit.set_user_controller(*setup.user);

  std::unique_ptr<port::Transport> owned;
  port::Transport* bus = request.transport;
  if (bus == nullptr) {
    owned = open_bus(request.bus, "--bus");
    bus = owned.get();
  }
  const port::ReceiveFilter filters[] = {{can::kSeatSensors.id, 0x7FFu},
                                         {can::kSeatInput.id, 0x7FFu}};
  bus->set_filters(filters, 2);
  if (request.listening) request.listening();

  ControllerNodeResult result;
  bool started = false, have_sensors = false;
  std::uint16_t sensors_counter = 0;
  double a_x = 0.0, x_r = 0.0;
  std::uint64_t last_n = 0;
  std::string bus_error;
  const auto answer = [&](std::uint64_t n, double force_n, double command_n) {
    ++result.samples;
    if (request.stop_after_s >= 0.0 && static_cast<double>(n) * dt_s >= request.stop_after_s) {
      ++result.silenced;
      return;
    }
    if (request.drop_every > 0 && (n + 1) % request.drop_every == 0) {
      ++result.dropped;
      return;
    }
    if (send_frame(*bus, can::make_command_frame(force_n, command_n, n)) ==
        port::TransportStatus::ok) {
      ++result.answered;
    } else {
      ++result.send_failures;
    }
  };
  Clock::time_point last_frame = Clock::now();
  for (;;) {
    if (request.stop_requested && request.stop_requested()) break;
    can::Frame frame;
    const port::TransportStatus status = bus->receive(frame, 200);
    if (status == port::TransportStatus::timeout) {
      const double idle_s = std::chrono::duration<double>(Clock::now() - last_frame).count();
      if (started && idle_s >= request.idle_exit_s) break;
      if (!started && request.first_sample_s > 0.0 && idle_s >= request.first_sample_s) {
        throw HostError(
            fmt::format("--bus {}: no sample within {} s", request.bus, request.first_sample_s));
      }
      continue;
    }
    if (status != port::TransportStatus::ok) {
      bus_error = fmt::format("controller: the bus {} failed ({}) after {} samples", request.bus,
                              port::transport_status_name(status), result.samples);
      break;
    }
    last_frame = Clock::now();
    const can::MessageSpec* spec = frame.id == can::kSeatSensors.id ? &can::kSeatSensors
                                   : frame.id == can::kSeatInput.id ? &can::kSeatInput
                                                                    : nullptr;
    if (spec == nullptr) continue;
    if (frame.length != can::kPayloadLength || !can::crc_ok(*spec, frame.data)) {
      ++result.corrupt_frames;
      continue;
    }
    const can::Payload payload = can::decode_payload(frame.data);
    if (spec == &can::kSeatSensors) {
      have_sensors = true;
      sensors_counter = payload.sample_counter;
      a_x = can::physical<double>(can::kSeatSensors.signals[0], payload.words[0]);
      x_r = can::physical<double>(can::kSeatSensors.signals[1], payload.words[1]);
      continue;
    }
    // SeatInput closes the sample; its sensors came first with the same counter.
    if (!have_sensors || sensors_counter != payload.sample_counter) continue;
    have_sensors = false;
    const double a_u = can::physical<double>(can::kSeatInput.signals[0], payload.words[0]);
    if (payload.sample_counter == 0 && (!started || last_n == 0)) {
      // The plant's greeting (re-sent until answered): start of the run.
      if (started) ++result.restarts;
      started = true;
      last_n = 0;
      unit.reset(a_u, setup.plant.x0_m);
      answer(0, unit.force_n(), 0.0);
      continue;
    }
    if (!started) continue;
    const std::uint16_t delta =
        static_cast<std::uint16_t>(payload.sample_counter - static_cast<std::uint16_t>(last_n));
    if (delta == 0) continue;  // the same sample again
    result.sample_gaps += delta - 1u;
    last_n += delta;
    const UnitSample<double> sample = unit.step(a_u, a_x, x_r, unit.force_n());
    answer(last_n, sample.next_force_n, sample.command_n);
  }
  result.bus_error = bus_error;
  result.json = controller_json(request, setup, result);
  return result;
}

}  // namespace stickslip::host
