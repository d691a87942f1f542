// The recordings replay and play stream (bus_commands.hpp): a CSV as SeatInput frames, a candump
// log as logged at its own rate, and the bits the frames take on the wire.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "bus_endpoint.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/can/frame_bits.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/rig_recording.hpp"

namespace stickslip::host {

void require_positive_dt(double dt_s, const char* option) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s))
    throw UsageError(fmt::format("{}: must be a positive time step in s, got {}", option, dt_s));
}

namespace {

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

BusRecording frames_from_csv(const std::string& path, const RecordingOptions& options,
                             const char* command) {
  RecordingReport report;
  const SampledSignal signal = read_continuous_recording(path, options, command, &report);
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

BusRecording frames_from_rig(const std::string& path) {
  const RigRecording rig = read_rig_recording(path);
  BusRecording recording;
  recording.t_s = rig.t_s;
  recording.dt_s = rig.dt_s;
  recording.recording_note = {};
  recording.frames.reserve(2 * rig.a_u_m_per_s2.size());
  const double no_travel = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t n = 0; n < rig.a_u_m_per_s2.size(); ++n) {
    bool saturated = false;
    // Sample n's sensors go out before its SeatInput (sensor_receiver.hpp).
    recording.frames.push_back(can::make_sensor_frame(
        rig.a_x_m_per_s2[n], rig.has_travel() ? rig.x_r_m[n] : no_travel, n, &saturated));
    bool input_saturated = false;
    recording.frames.push_back(can::make_input_frame(rig.a_u_m_per_s2[n], n, &input_saturated));
    if (saturated || input_saturated) ++recording.saturated;
  }
  return recording;
}

void BusLoad::add(const can::Frame& frame) {
  if (frame.flags & (can::kErrorFrame | can::kFd)) return;
  ++frames;
  bits_exact += can::frame_bits_exact(frame);
  bits_worst_case += can::frame_bits_worst_case(frame);
}

std::uint64_t realtime_now_us() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

namespace {

bool is_input_frame(const can::Frame& frame) {
  return frame.id == can::kSeatInput.id &&
         !(frame.flags & (can::kExtendedId | can::kRemote | can::kErrorFrame | can::kFd));
}

}  // namespace

double log_sample_interval_s(const std::vector<LoggedFrame>& logged) {
  std::vector<std::uint64_t> intervals_us;
  const LoggedFrame* previous = nullptr;
  for (const LoggedFrame& entry : logged) {
    if (!is_input_frame(entry.frame)) continue;
    if (previous != nullptr && entry.time_us > previous->time_us)
      intervals_us.push_back(entry.time_us - previous->time_us);
    else if (previous != nullptr)
      intervals_us.push_back(0);
    previous = &entry;
  }
  if (intervals_us.empty()) return 0.0;
  const auto middle = intervals_us.begin() + static_cast<std::ptrdiff_t>(intervals_us.size() / 2);
  std::nth_element(intervals_us.begin(), middle, intervals_us.end());
  return static_cast<double>(*middle) / 1e6;
}

LogInterval choose_log_interval(const std::string& path, double log_interval_s, double dt_s,
                                bool dt_given) {
  require_positive_dt(dt_s, "--dt");
  if (!(log_interval_s > 0.0)) return {dt_s, "--dt"};
  if (std::fabs(log_interval_s - dt_s) <= kLogRateTolerance * dt_s) return {dt_s, "--dt"};
  if (!dt_given) return {log_interval_s, "log"};
  throw UsageError(fmt::format(
      "{}: its SeatInput frames come every {} s ({} Hz) by their time stamps, but --dt is {} s "
      "(more than {} % apart); leave --dt out to run at the log's rate, give --dt {}, or add "
      "--retime when the time stamps are not the stream's (a capture of a faster playback)",
      path, log_interval_s, 1.0 / log_interval_s, dt_s, kLogRateTolerance * 100.0, log_interval_s));
}

BusRecording frames_from_log(const std::string& path, double dt_s, bool dt_given, bool log_times) {
  require_positive_dt(dt_s, "--dt");
  BusRecording recording;
  recording.logged = read_candump_log(path);
  if (recording.logged.empty()) throw HostError(path + ": the log holds no frames");
  const LogInterval interval =
      log_times ? choose_log_interval(path, log_sample_interval_s(recording.logged), dt_s, dt_given)
                : LogInterval{dt_s, "--dt"};
  recording.dt_s = interval.dt_s;
  recording.dt_source = interval.source;
  recording.frames.reserve(recording.logged.size());
  for (const LoggedFrame& entry : recording.logged) {
    recording.frames.push_back(entry.frame);
    if (entry.frame.id == can::kSeatInput.id && !(entry.frame.flags & can::kExtendedId)) {
      recording.t_s.push_back(static_cast<double>(recording.t_s.size()) * recording.dt_s);
    }
  }
  return recording;
}

BusRecording read_bus_recording(const std::string& path, double log_dt_s,
                                const RecordingOptions& recording, bool dt_given, bool log_times,
                                const char* command) {
  // --channel without --dbc goes to the recording reader, which refuses it: the log's frames
  // would be sent as they are, every bus's.
  return ends_with(path, ".log") && recording.dbc.empty() && recording.channel.empty()
             ? frames_from_log(path, log_dt_s, dt_given, log_times)
             : frames_from_csv(path, recording, command);
}

}  // namespace stickslip::host
