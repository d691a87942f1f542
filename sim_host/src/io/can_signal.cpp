#include "stickslip/host/io/can_signal.hpp"

#include <algorithm>
#include <cstdio>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

namespace {

// "can0, can1" ("(none)" for a log that records no channel), for messages.
std::string channel_list(const std::vector<std::string>& channels) {
  std::string list;
  for (const std::string& channel : channels)
    list += (list.empty() ? "" : ", ") + (channel.empty() ? std::string("(none)") : channel);
  return list;
}

}  // namespace

void require_channel(const CanLog& log, const std::string& log_path, std::string_view channel) {
  if (channel.empty()) return;
  const std::vector<std::string> channels = log_channels(log);
  if (std::find(channels.begin(), channels.end(), channel) == channels.end()) {
    throw UsageError("--channel " + std::string(channel) + ": " + log_path +
                     " has no frame on that channel (its channels: " + channel_list(channels) +
                     ")");
  }
}

SignalSeries extract_signal(const CanLog& log, const std::string& log_path, const Dbc& dbc,
                            std::string_view selector, std::string_view channel) {
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
  const auto of_message = [&](const LogFrame& frame) {
    return frame.id == message->id && frame.extended == message->extended;
  };
  require_channel(log, log_path, channel);
  if (channel.empty()) {
    std::vector<std::string> carrying;
    for (const LogFrame& frame : log.frames) {
      if (of_message(frame) &&
          std::find(carrying.begin(), carrying.end(), frame.channel) == carrying.end())
        carrying.push_back(frame.channel);
    }
    if (carrying.size() > 1) {
      std::sort(carrying.begin(), carrying.end());
      throw UsageError(log_path + ": message '" + message->name + "' is on channels " +
                       channel_list(carrying) + "; pick one bus with --channel NAME");
    }
  }
  SignalSeries series;
  series.name = std::string(selector);
  series.unit = signal->unit;
  series.frame_lines = log.format != CanLogFormat::kBlf;
  std::size_t on_channel = 0;  // data frames on the chosen channel (all without one)
  for (std::size_t n = 0; n < log.frames.size(); ++n) {
    const LogFrame& frame = log.frames[n];
    if (!channel.empty() && frame.channel != channel) continue;
    ++on_channel;
    if (!of_message(frame)) continue;
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
    const std::string among =
        " among its " + std::to_string(on_channel) + " data frames" +
        (channel.empty() ? std::string() : " on channel " + std::string(channel));
    throw HostError(log_path + ": no frame of message '" + message->name + "' (id " + id +
                    (message->extended ? ", extended" : "") + ")" +
                    (series.frames_too_short > 0
                         ? " long enough to hold signal '" + signal->name + "' (" +
                               std::to_string(series.frames_too_short) + " too short)"
                         : among));
  }
  return series;
}

}  // namespace stickslip::host
