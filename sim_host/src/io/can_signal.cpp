#include "stickslip/host/io/can_signal.hpp"

#include <cstdio>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

SignalSeries extract_signal(const CanLog& log, const std::string& log_path, const Dbc& dbc,
                            std::string_view selector) {
  const std::size_t dot = selector.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == selector.size()) {
    throw HostError("signal '" + std::string(selector) + "': expected MESSAGE.SIGNAL as " +
                    dbc.path + " names them");
  }
  const std::string_view message_name = selector.substr(0, dot);
  const std::string_view signal_name = selector.substr(dot + 1);
  const DbcMessage* message = dbc.find_message(message_name);
  if (message == nullptr) {
    std::string names;
    for (const DbcMessage& candidate : dbc.messages)
      names += (names.empty() ? "" : ", ") + candidate.name;
    throw HostError(dbc.path + ": no message '" + std::string(message_name) +
                    "' (the messages: " + names + ")");
  }
  const DbcSignal* signal = message->find_signal(signal_name);
  if (signal == nullptr) {
    std::string names;
    for (const DbcSignal& candidate : message->signals)
      names += (names.empty() ? "" : ", ") + candidate.name;
    throw HostError(dbc.path + ": message '" + message->name + "' has no signal '" +
                    std::string(signal_name) + "' (its signals: " + names + ")");
  }
  SignalSeries series;
  series.name = std::string(selector);
  series.unit = signal->unit;
  series.frame_lines = log.format != CanLogFormat::kBlf;
  for (std::size_t n = 0; n < log.frames.size(); ++n) {
    const LogFrame& frame = log.frames[n];
    if (frame.id != message->id || frame.extended != message->extended) continue;
    const std::optional<double> value = decode_signal(*signal, frame.data.data(), frame.length);
    if (!value) {
      ++series.frames_too_short;
      continue;
    }
    series.t_s.push_back(frame.time_s);
    series.values.push_back(*value);
    series.frames.push_back(series.frame_lines ? frame.line : n + 1);
  }
  if (series.values.empty()) {
    char id[16];
    std::snprintf(id, sizeof id, message->extended ? "0x%08X" : "0x%03X",
                  static_cast<unsigned>(message->id));
    throw HostError(
        log_path + ": no frame of message '" + message->name + "' (id " + id +
        (message->extended ? ", extended" : "") + ")" +
        (series.frames_too_short > 0
             ? " long enough to hold signal '" + signal->name + "' (" +
                   std::to_string(series.frames_too_short) + " too short)"
             : std::string(" among its ") + std::to_string(log.frames.size()) + " data frames"));
  }
  return series;
}

}  // namespace stickslip::host
