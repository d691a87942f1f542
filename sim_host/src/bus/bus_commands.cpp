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
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/output_file.hpp"
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

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void require_dt(double dt_s, const char* option) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s))
    throw UsageError(fmt::format("{}: must be a positive time step in s, got {}", option, dt_s));
}

EcuNodeConfig node_config(const SimulationSetup& setup, ScalarType scalar,
                          const can::CheckerConfig& checker, bool keep_trace) {
  EcuNodeConfig config;
  config.setup = setup;
  config.scalar = scalar;
  config.checker = checker;
  config.keep_trace = keep_trace;
  return config;
}

std::string with_bus_fields(const std::string& stats_json, const std::string& bus,
                            const can::FaultCounters& faults, const port::TransportCounters& node,
                            const port::TransportCounters& sender) {
  auto json = nlohmann::ordered_json::parse(stats_json);
  json["bus"] = bus;
  json["faults"] = nlohmann::ordered_json::parse(fault_counters_json(faults));
  json["receive_drops"] = node.receive_drops;
  json["malformed_reads"] = node.malformed_reads;
  json["send_failures"] = sender.send_failures;  // frames the bus could not carry (not sent)
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

BusRecording frames_from_csv(const std::string& path, const RecordingOptions& options) {
  RecordingReport report;
  const SampledSignal signal = read_continuous_recording(path, options, "replay", &report);
  BusRecording recording;
  recording.recording_note = describe_recording(path, report);
  recording.t_s = signal.t_s;
  recording.dt_s = signal.dt_s;
  recording.frames.reserve(signal.a_u_m_per_s2.size());
  for (std::size_t n = 0; n < signal.a_u_m_per_s2.size(); ++n) {
    bool saturated = false;
    recording.frames.push_back(can::make_input_frame(signal.a_u_m_per_s2[n], n, &saturated));
    if (saturated) ++recording.saturated;
  }
  return recording;
}

BusRecording frames_from_log(const std::string& path, double dt_s) {
  require_dt(dt_s, "--dt");
  const std::vector<LoggedFrame> logged = read_candump_log(path);
  BusRecording recording;
  recording.dt_s = dt_s;
  recording.frames.reserve(logged.size());
  for (const LoggedFrame& entry : logged) {
    recording.frames.push_back(entry.frame);
    if (entry.frame.id == can::kSeatInput.id && !(entry.frame.flags & can::kExtendedId)) {
      recording.t_s.push_back(static_cast<double>(recording.t_s.size()) * dt_s);
    }
  }
  if (recording.frames.empty()) throw HostError(path + ": the log holds no frames");
  return recording;
}

BusRecording read_bus_recording(const std::string& path, double log_dt_s,
                                const RecordingOptions& recording) {
  return ends_with(path, ".log") && recording.dbc.empty() ? frames_from_log(path, log_dt_s)
                                                          : frames_from_csv(path, recording);
}

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

ReplayResult replay_file(const ReplayRequest& request) {
  if (request.output_path.empty()) throw UsageError("--output: required");
  if (request.setup.reference) throw UsageError("--integrator reference: not available for replay");
  const BusRecording recording =
      read_bus_recording(request.input_path, request.log_dt_s, request.recording);
  SimulationSetup setup = request.setup;
  setup.params.dt_s = recording.dt_s;

  ReplayResult result;
  result.bus = request.bus;
  result.recording_note = recording.recording_note;
  result.input_saturated = recording.saturated;
  EcuNode node(node_config(setup, request.scalar, request.checker, true));  // may throw: first

  std::unique_ptr<port::Transport> sender = open_bus(request.bus, "--bus");
  std::unique_ptr<port::Transport> node_port = open_bus(request.bus, "--bus");
  // The sender listens to the node's outputs only (0x180..0x183).
  const port::ReceiveFilter outputs_only{can::kSeatMotion.id, can::kStandardIdMask & ~0x3u};
  sender->set_filters(&outputs_only, 1);

  const bool log_bus = !request.output_log_path.empty();
  const std::string log_interface = request.bus == "loopback" ? "vcan0" : request.bus;
  std::vector<LoggedFrame> bus_log;
  std::vector<can::Frame> outputs;
  outputs.reserve(16);

  const auto start = std::chrono::steady_clock::now();
  node.start(now_ns());
  std::uint64_t sent_ok = 0, node_received = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const std::uint64_t sample_us = static_cast<std::uint64_t>(
        std::llround(static_cast<double>(node.samples()) * recording.dt_s * 1e6));
    if (request.realtime) {
      std::this_thread::sleep_until(
          start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(static_cast<double>(i) * recording.dt_s)));
    }
    if (request.progress) request.progress(i, recording.frames.size());
    const can::Frame& frame = recording.frames[i];
    if (send_frame(*sender, frame) == port::TransportStatus::ok) {
      ++sent_ok;
      if (log_bus) bus_log.push_back({sample_us, log_interface, frame});
    }
    // Lock step: the node takes everything sent so far before the next frame goes out.
    while (node_received < sent_ok) {
      if (!node_takes_one(node, *node_port, request.receive_timeout_ms, outputs)) break;
      ++node_received;
      for (const can::Frame& out : outputs) {
        if (send_frame(*node_port, out) == port::TransportStatus::ok) ++result.output_frames;
        if (log_bus) bus_log.push_back({sample_us, log_interface, out});
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
  if (node.samples() < 2) {
    throw HostError(fmt::format("{}: the node received {} usable sample(s) over {}; need >= 2 ({})",
                                request.input_path, node.samples(), request.bus,
                                fault_counters_text(result.faults)));
  }
  result.summary = node.summary();

  if (log_bus) write_candump_log(request.output_log_path, bus_log);
  write_node_trace(request.output_path, node.trace(), recording.t_s, recording.dt_s);
  result.stats_json = with_bus_fields(
      format_stats_json(result.summary, StatsContext{&setup, request.scalar, request.input_path,
                                                     request.output_path}),
      request.bus, result.faults, result.node, result.sender);
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

// The ecu command's last line of stdout.
std::string ecu_json(const EcuRequest& request, const EcuResult& result, const EcuNode& node) {
  nlohmann::ordered_json json;
  json["bus"] = request.bus;
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
  json["faults"] = nlohmann::ordered_json::parse(fault_counters_json(result.faults));
  json["receive_drops"] = result.transport.receive_drops;
  json["malformed_reads"] = result.transport.malformed_reads;
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
  require_dt(request.setup.params.dt_s, "--dt");
  const bool keep_trace = !request.output_path.empty() || !request.sample_index_path.empty();
  if (request.receive_buffer_bytes < 0)
    throw UsageError(
        fmt::format("--receive-buffer: must be >= 0 bytes, got {}", request.receive_buffer_bytes));
  EcuNode node(node_config(request.setup, request.scalar, request.checker, keep_trace));
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
