// play and record (bus_commands.hpp): a recording's SeatInput frames sent on a bus at a multiple
// of real time without a node, or written as a candump log.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "bus_endpoint.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/error.hpp"

namespace stickslip::host {

namespace {

// The play command's last line of stdout.
std::string play_json(const PlayRequest& request, const PlayResult& result) {
  nlohmann::ordered_json json;
  json["bus"] = request.bus;
  json["input"] = request.input_path;
  json["speed"] = request.speed;
  json["frames"] = result.frames;
  json["attempted"] = result.attempted;
  json["sent"] = result.sent;
  json["not_sent"] = result.not_sent;
  json["interface_down"] = result.interface_down;
  json["buffer_full"] = result.buffer_full;
  json["other_failures"] = result.other_failures;
  json["first_not_sent"] =
      result.not_sent > 0 ? nlohmann::ordered_json(result.first_not_sent) : nullptr;
  json["last_not_sent"] =
      result.not_sent > 0 ? nlohmann::ordered_json(result.last_not_sent) : nullptr;
  json["duration_s"] = result.duration_s;
  json["max_late_s"] = result.max_late_s;
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

PlayResult play_file(const PlayRequest& request) {
  if (!(request.speed > 0.0) || !std::isfinite(request.speed))
    throw UsageError(fmt::format("--speed: must be a positive factor, got {}", request.speed));
  const BusRecording recording = read_bus_recording(
      request.input_path, request.log_dt_s, request.recording, request.log_dt_given, true, "play");
  std::unique_ptr<port::Transport> bus = open_bus(request.bus, "--bus");
  // The sender reads nothing: a filter no frame of the project matches (an extended id), so that
  // the kernel does not queue the whole bus for it.
  const port::ReceiveFilter nothing{can::kExtendedIdMask, can::kExtendedIdMask};
  bus->set_filters(&nothing, 1);
  PlayResult result;
  result.recording_note = recording.recording_note;
  result.frames = recording.frames.size();
  const double interval_s = recording.dt_s / request.speed;
  // Wakes at most once a millisecond and sends every frame due by then (at 10 kHz a sleep per
  // frame would cost more than the sending on a slow machine). A sender that fell behind (a busy
  // machine) catches up at no more than twice its rate: at most twice a batch's frames a wake,
  // so that it never floods the bus, nor runs through the rest of the recording in a burst.
  using Clock = std::chrono::steady_clock;
  const auto interval =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_s));
  const auto batch = std::max(interval, Clock::duration(std::chrono::milliseconds(1)));
  const std::size_t max_burst =
      2 * static_cast<std::size_t>(batch / std::max(interval, Clock::duration(1)));
  const auto start = Clock::now();
  std::size_t burst = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    if (request.stop != nullptr && *request.stop != 0) break;
    if (request.progress) request.progress(i, recording.frames.size());
    const auto due =
        start + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(static_cast<double>(i) * interval_s));
    if (Clock::now() < due) {
      std::this_thread::sleep_until(due + (batch - interval));
      burst = 0;
    } else if (++burst > max_burst) {
      std::this_thread::sleep_for(batch);
      burst = 0;
    }
    const double late_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - due).count();
    if (late_s > result.max_late_s) result.max_late_s = late_s;
    // A sensor keeps sampling while the bus is down: a frame the bus refuses is not sent and
    // not retried later (the node sees its counter missing); it is counted by the reason.
    const port::TransportStatus status = send_frame(*bus, recording.frames[i]);
    ++result.attempted;
    if (status == port::TransportStatus::ok) {
      ++result.sent;
      continue;
    }
    if (result.not_sent == 0) result.first_not_sent = i;
    result.last_not_sent = i;
    ++result.not_sent;
    if (status == port::TransportStatus::interface_down) {
      ++result.interface_down;
    } else if (status == port::TransportStatus::buffer_full) {
      ++result.buffer_full;
    } else {
      ++result.other_failures;
    }
  }
  result.duration_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bus->close();
  result.json = play_json(request, result);
  return result;
}

std::uint64_t record_log(const RecordRequest& request, std::uint64_t& saturated,
                         std::string* recording_note) {
  if (request.interface.empty()) throw UsageError("--interface: must not be empty");
  if (!(request.start_time_s < 0.0) && !(request.start_time_s < 1e10))
    throw UsageError(fmt::format("--start-time: must be s since the Unix epoch (0 .. 1e10), got {}",
                                 request.start_time_s));
  const BusRecording recording = frames_from_csv(request.input_path, request.recording, "record");
  if (recording_note != nullptr) *recording_note = recording.recording_note;
  // The wall clock at the start, then the recording's own time line: log2asc and other tools
  // date the log by its first time stamp (a log that starts at 0 is dated 1970).
  const std::uint64_t start_us =
      request.start_time_s < 0.0
          ? realtime_now_us()
          : static_cast<std::uint64_t>(std::llround(request.start_time_s * 1e6));
  std::vector<LoggedFrame> logged;
  logged.reserve(recording.frames.size());
  for (std::size_t n = 0; n < recording.frames.size(); ++n) {
    const double t = recording.t_s[n] - recording.t_s[0];
    logged.push_back({start_us + static_cast<std::uint64_t>(std::llround(t * 1e6)),
                      request.interface, recording.frames[n]});
  }
  write_candump_log(request.output_path, logged);
  saturated = recording.saturated;
  return logged.size();
}

}  // namespace stickslip::host
