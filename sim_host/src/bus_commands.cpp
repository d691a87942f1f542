#include "stickslip/host/bus_commands.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "stickslip/can/codec.hpp"
#include "stickslip/host/commands.hpp"
#include "stickslip/host/csv_reader.hpp"
#include "stickslip/host/output_file.hpp"
#include "stickslip/host/stats_json.hpp"

namespace stickslip::host {
namespace {

std::uint64_t now_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::unique_ptr<port::Transport> open_bus(const std::string& bus, const char* option) {
  std::unique_ptr<port::Transport> transport = port::make_transport(bus);
  const port::TransportStatus status = transport->open(bus);
  if (status != port::TransportStatus::ok) {
    throw HostError(fmt::format("{} {}: cannot open the bus: {}", option, bus,
                                port::transport_status_name(status)));
  }
  return transport;
}

// Sends, retrying briefly while the socket's queue is full (a real bus drains it).
port::TransportStatus send_frame(port::Transport& transport, const can::Frame& frame) {
  port::TransportStatus status = transport.send(frame);
  for (int attempt = 0; status == port::TransportStatus::buffer_full && attempt < 100; ++attempt) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    status = transport.send(frame);
  }
  return status;
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

BusRecording frames_from_csv(const std::string& path) {
  const SampledSignal signal = read_signal_csv(path);
  BusRecording recording;
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

BusRecording read_bus_recording(const std::string& path, double log_dt_s) {
  return ends_with(path, ".log") ? frames_from_log(path, log_dt_s) : frames_from_csv(path);
}

void write_node_trace(const std::string& path, const NodeTrace& trace, const std::vector<double>& t_s,
                      double dt_s) {
  AtomicOutputFile output(path);
  CsvWriter writer(output);
  writer.text(kSimulateHeader);
  writer.text("\n");
  const double t0 = t_s.empty() ? 0.0 : t_s[0];
  for (std::size_t row = 0; row < trace.index.size(); ++row) {
    const std::uint64_t n = trace.index[row];
    writer.number(n < t_s.size() ? t_s[n] : t0 + static_cast<double>(n) * dt_s);
    writer.separator();
    writer.number(trace.a_u[row]);
    writer.separator();
    writer.number(trace.x_r[row]);
    writer.separator();
    writer.number(trace.v_r[row]);
    writer.separator();
    writer.number(trace.a_x[row]);
    writer.separator();
    writer.number(trace.f_f[row]);
    writer.separator();
    writer.flag(trace.stuck[row] != 0);
    writer.end_row();
  }
  writer.flush();
  output.commit();
}

ReplayResult replay_file(const ReplayRequest& request) {
  if (request.output_path.empty()) throw UsageError("--output: required");
  if (request.setup.reference) throw UsageError("--integrator reference: not available for replay");
  const BusRecording recording = read_bus_recording(request.input_path, request.log_dt_s);
  SimulationSetup setup = request.setup;
  setup.params.dt_s = recording.dt_s;

  ReplayResult result;
  result.bus = request.bus;
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
    const can::Frame& frame = recording.frames[i];
    if (send_frame(*sender, frame) == port::TransportStatus::ok) {
      ++sent_ok;
      if (log_bus) bus_log.push_back({sample_us, log_interface, frame});
    }
    // Lock step: the node takes everything sent so far before the next frame goes out.
    while (node_received < sent_ok) {
      can::Frame received;
      const port::TransportStatus status = node_port->receive(received, request.receive_timeout_ms);
      if (status != port::TransportStatus::ok) {
        node.on_idle(now_ns());
        break;
      }
      ++node_received;
      node.on_frame(received, now_ns(), outputs);
      for (const can::Frame& out : outputs) {
        if (send_frame(*node_port, out) == port::TransportStatus::ok) ++result.output_frames;
        if (log_bus) bus_log.push_back({sample_us, log_interface, out});
      }
      outputs.clear();
    }
    can::Frame echoed;
    while (sender->receive(echoed, 0) == port::TransportStatus::ok) ++result.output_frames_received;
  }
  // The node's last outputs may still be on their way back.
  can::Frame echoed;
  while (result.output_frames_received < result.output_frames &&
         sender->receive(echoed, 100) == port::TransportStatus::ok)
    ++result.output_frames_received;

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
      format_stats_json(result.summary,
                        StatsContext{&setup, request.scalar, request.input_path, request.output_path}),
      request.bus, result.faults, result.node, result.sender);
  return result;
}

EcuResult run_ecu(const EcuRequest& request) {
  require_dt(request.setup.params.dt_s, "--dt");
  EcuNode node(node_config(request.setup, request.scalar, request.checker, !request.output_path.empty()));
  std::unique_ptr<port::Transport> bus = open_bus(request.bus, "--bus");
  EcuResult result;
  std::vector<can::Frame> outputs;
  outputs.reserve(16);
  node.start(now_ns());
  std::uint64_t counted = 0;  // frames for the node: all but other nodes' outputs
  while (!(request.stop != nullptr && *request.stop != 0) &&
         (request.max_frames == 0 || counted < request.max_frames)) {
    can::Frame frame;
    const port::TransportStatus status = bus->receive(frame, request.poll_ms);
    if (status == port::TransportStatus::timeout) {
      node.on_idle(now_ns());
      continue;
    }
    if (status != port::TransportStatus::ok) {
      if (request.stop != nullptr && *request.stop != 0) break;  // interrupted while waiting
      throw HostError(fmt::format("--bus {}: receive failed: {}", request.bus,
                                  port::transport_status_name(status)));
    }
    ++result.frames_received;
    if (node.on_frame(frame, now_ns(), outputs) != can::FrameVerdict::ignored_output) ++counted;
    for (const can::Frame& out : outputs)
      if (send_frame(*bus, out) == port::TransportStatus::ok) ++result.output_frames;
    outputs.clear();
  }
  result.faults = node.counters();
  result.transport = bus->counters();
  bus->close();
  result.summary = node.summary();
  if (!request.output_path.empty()) {
    write_node_trace(request.output_path, node.trace(), {}, request.setup.params.dt_s);
  }
  nlohmann::ordered_json json;
  json["bus"] = request.bus;
  json["frames_received"] = result.frames_received;
  json["samples"] = node.samples();
  json["output_frames"] = result.output_frames;
  json["T_ax"] = result.summary.transmissibility;
  json["p_stick"] = result.summary.stick_probability;
  json["K"] = result.summary.den_hartog_k;
  json["faults"] = nlohmann::ordered_json::parse(fault_counters_json(result.faults));
  json["receive_drops"] = result.transport.receive_drops;
  json["malformed_reads"] = result.transport.malformed_reads;
  result.json = json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  return result;
}

std::uint64_t record_log(const RecordRequest& request, std::uint64_t& saturated) {
  if (request.interface.empty()) throw UsageError("--interface: must not be empty");
  const BusRecording recording = frames_from_csv(request.input_path);
  std::vector<LoggedFrame> logged;
  logged.reserve(recording.frames.size());
  for (std::size_t n = 0; n < recording.frames.size(); ++n) {
    const double t = recording.t_s[n] - recording.t_s[0];
    logged.push_back({static_cast<std::uint64_t>(std::llround(t * 1e6)), request.interface,
                      recording.frames[n]});
  }
  write_candump_log(request.output_path, logged);
  saturated = recording.saturated;
  return logged.size();
}

}  // namespace stickslip::host
