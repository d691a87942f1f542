// stickslip record and play: a recording's SeatInput frames into a candump log, or onto a bus
// without a node (bus_commands.hpp).
#include <fmt/format.h>

#include <ostream>

#include "command.hpp"
#include "recording_options.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stop_signals.hpp"

namespace stickslip::host {
namespace {

class RecordCommand : public Command {
 public:
  void add_options(Options& record) override {
    record.add_option("--input", request_.input_path, "recording as simulate reads it")->required();
    record.add_option("--output", request_.output_path, "candump log to write")->required();
    record.add_option("--interface", request_.interface, "interface name in the log")
        ->capture_default_str();
    recording_.add_to(record);
    record.add_option("--start-time", request_.start_time_s,
                      "time stamp of the first frame, s since the Unix epoch (default: the wall "
                      "clock, CLOCK_REALTIME, when record starts)");
  }

  int run(Options&, std::ostream& out, std::ostream& err) override {
    RecordRequest request = request_;
    request.recording = recording_.resolve();
    std::uint64_t saturated = 0;
    std::string note;
    const std::uint64_t frames = record_log(request, saturated, &note);
    if (!note.empty()) err << "stickslip: " << note << "\n";
    out << fmt::format("wrote {}: {} SeatInput frames on {}, {} samples saturated\n",
                       request_.output_path, frames, request_.interface, saturated);
    return kExitOk;
  }

 private:
  RecordRequest request_;
  RecordingOptionGroup recording_;
};

class PlayCommand : public Command {
 public:
  void add_options(Options& play) override {
    play.add_option("--input", request_.input_path, "CSV (t,a_u) or candump log (*.log)")
        ->required();
    play.add_option("--bus", request_.bus, "loopback | a SocketCAN interface such as vcan0")
        ->required();
    play.add_option("--speed", request_.speed, "times real time")->capture_default_str();
    play.add_option("--dt", request_.log_dt_s,
                    "sample interval of a candump-log input, s (default: the log's own rate, "
                    "else 0.001)")
        ->capture_default_str();
    play.add_flag("--progress", progress_,
                  "frames sent on stderr once a second (default: on a terminal)");
    recording_.add_to(play, false);
  }

  int run(Options& play, std::ostream& out, std::ostream& err) override {
    PlayRequest request = request_;
    request.log_dt_given = given(play, "--dt");
    check_bus_name("--bus", request_.bus);
    request.recording = recording_.resolve();
    const StopOnSignals signals;
    request.stop = &stop_requested;
    std::function<void(std::uint64_t, std::uint64_t)> progress = make_frame_progress(
        err, "play", progress_ || stderr_is_terminal(err),
        fmt::format("play: sending {} on {} at {}x real time until its end, SIGINT or SIGTERM",
                    request.input_path, request.bus, request.speed));
    request.progress = bus_progress(progress);
    const PlayResult result = play_file(request);
    if (!result.recording_note.empty()) err << "stickslip: " << result.recording_note << "\n";
    out << fmt::format(
        "played {} on {} at {}x: {} of {} frames sent, {} not sent ({} interface "
        "down, {} buffer full, {} other)\n",
        request.input_path, request.bus, request.speed, result.sent, result.frames, result.not_sent,
        result.interface_down, result.buffer_full, result.other_failures);
    out << result.json << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  PlayRequest request_;
  bool progress_ = false;
  RecordingOptionGroup recording_;
};

}  // namespace

std::unique_ptr<Command> make_record_command() {
  return std::make_unique<RecordCommand>();
}

std::unique_ptr<Command> make_play_command() {
  return std::make_unique<PlayCommand>();
}

}  // namespace stickslip::host
