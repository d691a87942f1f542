#include "stickslip/host/bus/bus_commands.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <thread>

#include "bus_endpoint.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/io/trace_csv.hpp"
#include "stickslip/host/run/stats_json.hpp"

namespace stickslip::host {
namespace {

std::uint64_t now_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

// The clock of the kernel's receive time stamps (SO_TIMESTAMPNS).
std::uint64_t realtime_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

void add_counters(port::TransportCounters& sum, const port::TransportCounters& more) {
  sum.frames_sent += more.frames_sent;
  sum.frames_received += more.frames_received;
  sum.receive_drops += more.receive_drops;
  sum.malformed_reads += more.malformed_reads;
  sum.send_failures += more.send_failures;
}

EcuNodeConfig node_config(const SimulationSetup& setup, ScalarType scalar,
                          const can::CheckerConfig& checker, bool keep_trace, unsigned output_every,
                          OutputSet outputs, bool estimator = false) {
  EcuNodeConfig config;
  config.estimator = estimator;
  config.setup = setup;
  config.scalar = scalar;
  config.checker = checker;
  config.keep_trace = keep_trace;
  config.output_every = output_every;
  config.outputs = outputs;
  return config;
}

// The bus load of the frames replay put on the bus over the stream's duration, exact and worst
// case (frame_bits.hpp), as bits per second and as a share of 1 M, 500 k and 250 kbit/s.
nlohmann::ordered_json bus_load_json(const BusLoad& load, double duration_s) {
  nlohmann::ordered_json json;
  json["frames"] = load.frames;
  json["duration_s"] = duration_s;
  const double exact = static_cast<double>(load.bits_exact) / duration_s;
  const double worst = static_cast<double>(load.bits_worst_case) / duration_s;
  json["bits_per_s_exact"] = exact;
  json["bits_per_s_worst_case"] = worst;
  for (const double bitrate : {1e6, 5e5, 2.5e5}) {
    const std::string rate = fmt::format("{}k", bitrate / 1e3);
    json["percent_exact_" + rate] = 100.0 * exact / bitrate;
    json["percent_worst_case_" + rate] = 100.0 * worst / bitrate;
  }
  return json;
}

const char* output_set_name(OutputSet outputs) {
  switch (outputs) {
    case OutputSet::reduced:
      return "reduced";
    case OutputSet::motion:
      return "motion";
    default:
      return "full";
  }
}

std::string with_bus_fields(const std::string& stats_json, const ReplayRequest& request,
                            const BusRecording& recording, const BusLoad& load,
                            std::uint64_t samples, const can::FaultCounters& faults,
                            const port::TransportCounters& node,
                            const port::TransportCounters& sender) {
  auto json = nlohmann::ordered_json::parse(stats_json);
  json["bus"] = request.bus;
  json["dt_source"] = recording.dt_source;
  json["e2e"] = request.checker.e2e;  // false: plain sensor frames, no CRC or counter checks
  json["outputs"] = output_set_name(request.outputs);
  json["output_every"] = request.output_every;
  json["bus_load"] = bus_load_json(load, static_cast<double>(samples) * recording.dt_s);
  json["faults"] = nlohmann::ordered_json::parse(fault_counters_json(faults));
  json["receive_drops"] = node.receive_drops;
  json["malformed_reads"] = node.malformed_reads;
  json["send_failures"] = sender.send_failures;  // frames the bus could not carry (not sent)
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

void write_node_trace(const std::string& path, const NodeTrace& trace,
                      const std::vector<double>& t_s, double dt_s) {
  AtomicOutputFile output(path);
  CsvWriter writer(output);
  TraceCsvWriter csv(writer);
  const double t0 = t_s.empty() ? 0.0 : t_s[0];
  for (std::size_t row = 0; row < trace.index.size(); ++row) {
    const std::uint64_t n = trace.index[row];
    csv.row({n < t_s.size() ? t_s[n] : t0 + static_cast<double>(n) * dt_s, trace.a_u[row],
             trace.x_r[row], trace.v_r[row], trace.a_x[row], trace.f_f[row],
             trace.stuck[row] != 0});
  }
  csv.flush();
  output.commit();
}

namespace {

// The node receives one frame and answers it into `outputs`; false (silence counted) when none
// came within the timeout.
bool node_takes_one(EcuNode& node, port::Transport& node_port, int timeout_ms,
                    std::vector<can::Frame>& outputs) {
  can::Frame received;
  if (node_port.receive(received, timeout_ms) != port::TransportStatus::ok) {
    node.on_idle(now_ns());
    return false;
  }
  node.on_frame(received, now_ns(), outputs);
  return true;
}

// The node's last outputs may still be on their way back to the sender.
void receive_last_outputs(port::Transport& sender, ReplayResult& result) {
  can::Frame echoed;
  while (result.output_frames_received < result.output_frames &&
         sender.receive(echoed, 100) == port::TransportStatus::ok)
    ++result.output_frames_received;
}

}  // namespace

namespace {

// Where each frame goes in replay's output log (ReplayRequest::retime): a log's frames keep
// their own time stamp and interface, the node's outputs take those of the frame they answer;
// otherwise sample n is at the start (CLOCK_REALTIME) + n * dt on the bus's interface.
class BusLogStamps {
 public:
  BusLogStamps(const ReplayRequest& request, const BusRecording& recording)
      : recording_(recording),
        own_(!request.retime && !recording.logged.empty()),
        interface_(request.bus == "loopback" ? "vcan0" : request.bus),
        start_us_(realtime_now_us()) {}
  LoggedFrame stamp(std::size_t frame, std::uint64_t samples, const can::Frame& what) const {
    if (own_) return {recording_.logged[frame].time_us, recording_.logged[frame].interface, what};
    const auto offset_us = static_cast<std::uint64_t>(
        std::llround(static_cast<double>(samples) * recording_.dt_s * 1e6));
    return {start_us_ + offset_us, interface_, what};
  }

 private:
  const BusRecording& recording_;
  bool own_;
  std::string interface_;
  std::uint64_t start_us_;
};

void require_two_samples(const ReplayRequest& request, std::uint64_t samples,
                         const can::FaultCounters& faults) {
  if (samples >= 2) return;
  throw HostError(fmt::format("{}: the node received {} usable sample(s) over {}; need >= 2 ({})",
                              request.input_path, samples, request.bus,
                              fault_counters_text(faults)));
}

}  // namespace

ReplayResult replay_file(const ReplayRequest& request) {
  if (request.output_path.empty()) throw UsageError("--output: required");
  if (request.setup.reference) throw UsageError("--integrator reference: not available for replay");
  const BusRecording recording =
      request.estimator
          ? frames_from_rig(request.input_path)
          : read_bus_recording(request.input_path, request.log_dt_s, request.recording,
                               request.log_dt_given, !request.retime);
  SimulationSetup setup = request.setup;
  setup.params.dt_s = recording.dt_s;

  ReplayResult result;
  result.bus = request.bus;
  result.recording_note = recording.recording_note;
  result.input_saturated = recording.saturated;
  EcuNode node(node_config(setup, request.scalar, request.checker, true, request.output_every,
                           request.outputs, request.estimator));  // may throw: first

  std::unique_ptr<port::Transport> sender = open_bus(request.bus, "--bus");
  std::unique_ptr<port::Transport> node_port = open_bus(request.bus, "--bus");
  // The sender listens to the node's outputs only (0x180..0x187).
  const port::ReceiveFilter outputs_only{can::kSeatMotion.id, can::kStandardIdMask & ~0x7u};
  sender->set_filters(&outputs_only, 1);

  const bool log_bus = !request.output_log_path.empty();
  const BusLogStamps stamps(request, recording);
  std::vector<LoggedFrame> bus_log;
  std::vector<can::Frame> outputs;
  outputs.reserve(16);

  const auto start = std::chrono::steady_clock::now();
  node.start(now_ns());
  std::uint64_t sent_ok = 0, node_received = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const std::uint64_t samples = node.samples();
    if (request.realtime) {
      std::this_thread::sleep_until(
          start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(static_cast<double>(i) * recording.dt_s)));
    }
    if (request.progress) request.progress(i, recording.frames.size());
    const can::Frame& frame = recording.frames[i];
    if (send_frame(*sender, frame) == port::TransportStatus::ok) {
      ++sent_ok;
      result.bus_load.add(frame);
      if (log_bus) bus_log.push_back(stamps.stamp(i, samples, frame));
    }
    // Lock step: the node takes everything sent so far before the next frame goes out.
    while (node_received < sent_ok) {
      if (!node_takes_one(node, *node_port, request.receive_timeout_ms, outputs)) break;
      ++node_received;
      for (const can::Frame& out : outputs) {
        if (send_frame(*node_port, out) == port::TransportStatus::ok) {
          ++result.output_frames;
          result.bus_load.add(out);
        }
        if (log_bus) bus_log.push_back(stamps.stamp(i, samples, out));
      }
      outputs.clear();
    }
    can::Frame echoed;
    while (sender->receive(echoed, 0) == port::TransportStatus::ok) ++result.output_frames_received;
  }
  receive_last_outputs(*sender, result);

  result.frames_sent = sent_ok;
  result.faults = node.counters();
  result.sender = sender->counters();
  result.node = node_port->counters();
  sender->close();
  node_port->close();
  require_two_samples(request, node.samples(), result.faults);
  result.summary = node.summary();

  if (log_bus) write_candump_log(request.output_log_path, bus_log);
  write_node_trace(request.output_path, node.trace(), recording.t_s, recording.dt_s);
  result.stats_json = with_bus_fields(
      format_stats_json(result.summary, StatsContext{&setup, request.scalar, request.input_path,
                                                     request.output_path}),
      request, recording, result.bus_load, node.samples(), result.faults, result.node,
      result.sender);
  if (node.estimator())
    result.estimator_limits = estimator_limits(node.estimator_report().sensors, node.samples());
  return result;
}

namespace {

// The bus going down is an event of the run, not an error: the node keeps its state and its
// sequence check, so the samples the sender could not send while the bus was down show up as a
// gap (lost or skipped) with the first frame after it. The kernel reports the down once, to
// whichever call comes first (a receive, or an output send), and sends fail while it lasts:
// `down` is set by the first such failure and cleared by the next output frame that goes out
// (frames queued before the down are still received while it lasts).
class BusDownCounter {
 public:
  explicit BusDownCounter(std::uint64_t& count) : count_(count) {}
  void failed(port::TransportStatus status) {
    if (status != port::TransportStatus::interface_down &&
        status != port::TransportStatus::no_such_interface)
      return;
    if (!down_) ++count_;
    down_ = true;
  }
  void output_sent() { down_ = false; }

 private:
  std::uint64_t& count_;
  bool down_ = false;
};

// At most this many queued frames are still taken after a stop (a bus that never goes quiet).
constexpr std::uint64_t kMaxDrainFrames = 1000000;

// The state estimator's part of the ecu JSON (--estimator): the SeatSensors counters, the last
// estimates (friction levels null until converged) and what it could not estimate.
nlohmann::ordered_json estimator_json(const EcuNode& node) {
  const EstimatorReport r = node.estimator_report();
  nlohmann::ordered_json out;
  out["sensor_frames"] = r.sensors.frames;
  out["sensor_accepted"] = r.sensors.accepted;
  out["sensor_refused"] = r.sensors.refused;
  out["sensor_unused"] = r.sensors.unused;
  out["samples_with_a_x"] = r.sensors.with_a_x;
  out["samples_with_travel"] = r.sensors.with_travel;
  out["x_r"] = r.x_r_m;
  out["v_r"] = r.v_r_m_per_s;
  out["f_f"] = r.friction_n;
  out["ffk"] = r.kinetic_converged ? nlohmann::ordered_json(r.kinetic_friction_n) : nullptr;
  out["ffs"] = r.static_converged ? nlohmann::ordered_json(r.static_friction_n) : nullptr;
  out["breakaways"] = r.breakaways;
  out["cannot_estimate"] = estimator_limits(r.sensors, node.samples());
  return out;
}

// The ecu command's last line of stdout.
std::string ecu_json(const EcuRequest& request, const EcuResult& result, const EcuNode& node) {
  nlohmann::ordered_json json;
  json["bus"] = request.bus;
  json["e2e"] = request.checker.e2e;  // false: plain sensor frames, no CRC or counter checks
  json["outputs"] = output_set_name(request.outputs);
  json["output_every"] = request.output_every;
  json["frames_received"] = result.frames_received;
  json["samples"] = node.samples();
  // The sender's sample numbers of the first and last row (null: none yet).
  json["first_sample"] = node.samples() > 0 ? nlohmann::ordered_json(node.first_sample()) : nullptr;
  json["last_sample"] = node.samples() > 0 ? nlohmann::ordered_json(node.last_sample()) : nullptr;
  json["output_frames"] = result.output_frames;
  json["output_send_failures"] = result.output_send_failures;
  json["bus_down"] = result.bus_down;
  json["left_after_stop"] = result.left_after_stop;
  json["T_ax"] = result.summary.transmissibility;
  json["p_stick"] = result.summary.stick_probability;
  json["K"] = result.summary.den_hartog_k;
  if (result.summary.end_stops) json["end_stop_contacts"] = result.summary.end_stop_contacts;
  json["faults"] = nlohmann::ordered_json::parse(fault_counters_json(result.faults));
  json["receive_drops"] = result.transport.receive_drops;
  json["malformed_reads"] = result.transport.malformed_reads;
  if (node.estimator()) json["estimator"] = estimator_json(node);
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

// Stopped by a signal: first the frames the kernel had already queued for the node (received
// before the stop, by their kernel time stamp), so that a node that lags behind the bus ends
// with the last sample sent before the stop. The first later frame ends it, unused (counted).
void drain_after_stop(port::Transport& bus, const std::function<void(const can::Frame&)>& take,
                      std::uint64_t& left_after_stop) {
  const std::uint64_t stop_ns = realtime_ns();
  can::Frame frame;
  for (std::uint64_t n = 0;
       n < kMaxDrainFrames && bus.receive(frame, 0) == port::TransportStatus::ok; ++n) {
    if (frame.timestamp_ns > stop_ns) {
      ++left_after_stop;
      break;
    }
    take(frame);
  }
}

}  // namespace

EcuResult run_ecu(const EcuRequest& request) {
  require_positive_dt(request.setup.params.dt_s, "--dt");
  const bool keep_trace = !request.output_path.empty() || !request.sample_index_path.empty();
  if (request.receive_buffer_bytes < 0)
    throw UsageError(
        fmt::format("--receive-buffer: must be >= 0 bytes, got {}", request.receive_buffer_bytes));
  EcuNode node(node_config(request.setup, request.scalar, request.checker, keep_trace,
                           request.output_every, request.outputs, request.estimator));
  std::unique_ptr<port::Transport> bus =
      open_bus(request.bus, "--bus", request.receive_buffer_bytes);
  EcuResult result;
  std::vector<can::Frame> outputs;
  outputs.reserve(16);
  node.start(now_ns());
  const auto stopped = [&request] { return request.stop != nullptr && *request.stop != 0; };
  BusDownCounter bus_down{result.bus_down};
  port::TransportCounters earlier;  // of the endpoints before a reopen
  std::uint64_t counted = 0;        // frames for the node: all but other nodes' outputs
  const std::function<void(const can::Frame&)> take = [&](const can::Frame& frame) {
    ++result.frames_received;
    if (node.on_frame(frame, now_ns(), outputs) != can::FrameVerdict::ignored_output) ++counted;
    for (const can::Frame& out : outputs) {
      const port::TransportStatus sent = send_frame(*bus, out);
      if (sent == port::TransportStatus::ok) {
        ++result.output_frames;
        bus_down.output_sent();
      } else {
        ++result.output_send_failures;
        bus_down.failed(sent);
      }
    }
    outputs.clear();
  };
  while (!stopped() && (request.max_frames == 0 || counted < request.max_frames)) {
    if (request.progress) request.progress(counted, request.max_frames);
    can::Frame frame;
    const port::TransportStatus status = bus->receive(frame, request.poll_ms);
    if (status == port::TransportStatus::timeout) {
      node.on_idle(now_ns());
      continue;
    }
    if (status != port::TransportStatus::ok) {
      if (stopped()) break;  // interrupted while waiting
      if (status == port::TransportStatus::interface_down) {
        bus_down.failed(status);  // the socket stays bound: frames arrive again once it is up
        continue;
      }
      if (status == port::TransportStatus::no_such_interface) {
        // Deleted (and the socket unbound): open it again once it is back.
        bus_down.failed(status);
        add_counters(earlier, bus->counters());  // open() starts the endpoint's counters again
        while (!stopped() && bus->open(request.bus) != port::TransportStatus::ok) {
          node.on_idle(now_ns());
          std::this_thread::sleep_for(std::chrono::milliseconds(request.poll_ms));
        }
        continue;
      }
      throw HostError(fmt::format("--bus {}: receive failed: {}", request.bus,
                                  port::transport_status_name(status)));
    }
    take(frame);
  }
  if (stopped()) drain_after_stop(*bus, take, result.left_after_stop);
  result.faults = node.counters();
  result.transport = bus->counters();
  add_counters(result.transport, earlier);
  bus->close();
  result.summary = node.summary();
  if (!request.output_path.empty()) {
    write_node_trace(request.output_path, node.trace(), {}, request.setup.params.dt_s);
  }
  if (!request.sample_index_path.empty())
    write_sample_index(request.sample_index_path, node.trace());
  result.json = ecu_json(request, result, node);
  if (node.estimator())
    result.estimator_limits = estimator_limits(node.estimator_report().sensors, node.samples());
  return result;
}

void write_sample_index(const std::string& path, const NodeTrace& trace) {
  AtomicOutputFile output(path);
  CsvWriter writer(output);
  writer.text("n,sample,held\n");
  for (std::size_t row = 0; row < trace.index.size(); ++row) {
    writer.number(static_cast<double>(trace.index[row]));
    writer.separator();
    writer.number(static_cast<double>(trace.sample[row]));
    writer.separator();
    writer.flag(trace.held[row] != 0);
    writer.end_row();
  }
  writer.flush();
  output.commit();
}

}  // namespace stickslip::host
