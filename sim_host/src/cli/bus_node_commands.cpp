// stickslip replay and ecu: the ECU node over a bus (bus_commands.hpp), with the model options
// the node can run (kBusNodeChoices).
#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <ostream>
#include <string>

#include "command.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stop_signals.hpp"

namespace stickslip::host {
namespace {

constexpr const char* kNodeSceneHelp =
    "scene file (TOML, docs/scenes/): seat, model, integrator, sample rate, CAN ids; the flags "
    "override it";

// The receive check and the node's outputs, as replay and ecu share them.
struct NodeOptions {
  bool no_e2e = false;
  unsigned output_every = 1;
  std::string outputs = "full";

  void add_to(Options& command, can::CheckerConfig& checker) {
    command
        .add_option("--max-gap", checker.max_gap,
                    "lost samples held per gap; a longer gap is a counted resync")
        ->capture_default_str();
    command.add_flag("--no-e2e", no_e2e,
                     "the sender has no E2E counter or CRC (plain sensor frames, a_u in bytes "
                     "4-5): every SeatInput frame is the next sample");
    command
        .add_option("--output-every", output_every,
                    "output cycle: SeatMotion/SeatForce every this many samples")
        ->capture_default_str()
        ->check(OptionCheck::at_least_one);
    command
        .add_option("--outputs", outputs,
                    "full (SeatMotion, SeatForce, SeatStats, SeatScene), reduced (SeatMotion, "
                    "SeatStats: fits 250 and 500 kbit/s buses; docs/CAN.md) or motion "
                    "(SeatMotion, SeatForce only: a node without running statistics)")
        ->capture_default_str();
  }

  template <typename Request>
  void apply(Request& request) const {
    request.checker.e2e = !no_e2e;
    request.output_every = output_every;
    if (outputs == "full") {
      request.outputs = OutputSet::full;
    } else if (outputs == "reduced") {
      request.outputs = OutputSet::reduced;
    } else if (outputs == "motion") {
      request.outputs = OutputSet::motion;
    } else {
      throw UsageError("--outputs: unknown set '" + outputs +
                       "' (expected full, reduced or motion)");
    }
  }
};

class ReplayCommand : public Command {
 public:
  void add_options(Options& replay) override {
    replay.add_option("--input", request_.input_path, "CSV (t,a_u) or candump log (*.log)")
        ->required();
    replay.add_option("--bus", request_.bus, "loopback | a SocketCAN interface such as vcan0")
        ->capture_default_str();
    replay.add_option("--pace", pace_, "max | realtime")->capture_default_str();
    replay.add_option("--output", request_.output_path, "CSV file to write")->required();
    replay.add_option("--output-log", request_.output_log_path,
                      "also write every frame on the bus as a candump log");
    replay
        .add_option("--dt", request_.log_dt_s,
                    "sample interval of a candump-log input, s (default: the log's own rate, "
                    "else 0.001); a log whose rate differs by more than 1 % is refused")
        ->capture_default_str();
    replay.add_flag("--retime", request_.retime,
                    "a log's time stamps are not the stream's (a capture of a faster playback): "
                    "run it at --dt, and time --output-log n * dt from now on the bus's interface");
    node_.add_to(replay, request_.checker);
    replay.add_flag("--estimator", request_.estimator,
                    "the input is a rig recording (t,a_u,a_x[,x_r]): send its sensors in "
                    "SeatSensors and run the node's state estimator (docs/CAN.md)");
    replay.add_flag("--progress", progress_,
                    "frames sent on stderr once a second (default: on a terminal)");
    model_.add_to(replay, request_.setup, kNodeSceneHelp);
    recording_.add_to(replay, false, false);
    replay
        .add_option("--rate", rate_,
                    "text without a time column: sample rate, Hz (max | realtime: --pace, as "
                    "spelt before)")
        ->group("Recording");
  }

  int run(Options& replay, std::ostream& out, std::ostream& err) override {
    ReplayRequest request = request_;
    check_bus_name("--bus", request_.bus);
    request.recording = recording_.resolve();
    // --dt of a recording that is no SeatInput log: the node's step, to resample it to.
    if (given(replay, "--dt")) request.recording.dt_s = request.log_dt_s;
    const ResolvedModel model = model_.resolve(replay, request.setup);
    request.scalar = model.scalar;
    node_.apply(request);
    if (model.scene_dt_s() > 0.0 && !given(replay, "--dt")) request.log_dt_s = model.scene_dt_s();
    request.log_dt_given = given(replay, "--dt") || model.scene_dt_s() > 0.0;
    const std::string pace = resolve_pace(replay, request.recording);
    if (pace == "realtime") {
      request.realtime = true;
    } else if (pace != "max") {
      throw UsageError("--pace: unknown pace '" + pace + "' (expected max or realtime)");
    }
    std::function<void(std::uint64_t, std::uint64_t)> progress = make_frame_progress(
        err, "replay", progress_ || stderr_is_terminal(err),
        request.realtime ? fmt::format("replay: streaming {} over {} in real time: as long as the "
                                       "recording lasts (--pace max does not wait)",
                                       request.input_path, request.bus)
                         : std::string());
    request.progress = bus_progress(progress);
    const ReplayResult result = replay_file(request);
    if (!result.recording_note.empty()) err << "stickslip: " << result.recording_note << "\n";
    out << fmt::format(
        "replayed {} over {}: {} frames sent, {} samples, {} output frames ({} seen "
        "back), {} input samples saturated\n",
        request.input_path, result.bus, result.frames_sent, result.summary.samples,
        result.output_frames, result.output_frames_received, result.input_saturated);
    out << fault_counters_text(result.faults) << "\n";
    if (!result.estimator_limits.empty()) out << "estimator: " << result.estimator_limits << "\n";
    out << result.stats_json << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  // --rate HZ is the recording's sample rate, as on every command that reads one; --rate max and
  // --rate realtime, words that no rate can be, stay the pace they named before --pace.
  std::string resolve_pace(Options& replay, RecordingOptions& recording) const {
    if (!given(replay, "--rate")) return pace_;
    if (rate_ == "max" || rate_ == "realtime") {
      if (given(replay, "--pace") && pace_ != rate_)
        throw UsageError("--rate " + rate_ + " and --pace " + pace_ + ": give one pace");
      return rate_;
    }
    double rate_hz = 0.0;
    std::size_t used = 0;
    try {
      rate_hz = std::stod(rate_, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != rate_.size() || !std::isfinite(rate_hz) || !(rate_hz > 0.0)) {
      throw UsageError("--rate: '" + rate_ +
                       "' is neither a sample rate > 0 (Hz) nor max or realtime (the pace)");
    }
    recording.rate_hz = rate_hz;
    return pace_;
  }

  ReplayRequest request_;
  NodeOptions node_;
  std::string pace_ = "max", rate_;
  bool progress_ = false;
  ModelOptions model_{kBusNodeChoices};
  RecordingOptionGroup recording_;
};

class EcuCommand : public Command {
 public:
  void add_options(Options& ecu) override {
    ecu.add_option("--bus", request_.bus,
                   "a SocketCAN interface such as vcan0 (the loopback bus has no sender outside "
                   "this process: replay runs the node on it)")
        ->required();
    ecu.add_option(
           "--frames", request_.max_frames,
           "stop after this many frames for the node (all but other nodes' outputs; 0: never)")
        ->capture_default_str();
    ecu.add_option("--timeout", timeout_s_, "stop after this many seconds (0: never)")
        ->capture_default_str()
        ->check(OptionCheck::non_negative);
    ecu.add_option("--dt", request_.setup.params.dt_s, "sample interval of the stream, s")
        ->capture_default_str();
    ecu.add_option("--output", request_.output_path, "write the node's samples as simulate does");
    ecu.add_option("--receive-buffer", request_.receive_buffer_bytes,
                   "SocketCAN receive buffer (SO_RCVBUF), bytes; 0: the kernel's default")
        ->capture_default_str();
    ecu.add_option(
        "--sample-index", request_.sample_index_path,
        "write n,sample,held per row: the sender's sample number of each row, 1 if held");
    node_.add_to(ecu, request_.checker);
    ecu.add_flag("--estimator", request_.estimator,
                 "run the state estimator on SeatInput + SeatSensors (measured a_x, x_r) and "
                 "publish SeatEstimate, SeatEstimateForce, FrictionEstimate (docs/CAN.md)");
    ecu.add_flag("--progress", progress_,
                 "frames taken on stderr once a second (default: on a terminal)");
    model_.add_to(ecu, request_.setup, kNodeSceneHelp);
  }

  int run(Options& ecu, std::ostream& out, std::ostream& err) override {
    check_bus_name("--bus", request_.bus);
    EcuRequest request = request_;
    const ResolvedModel model = model_.resolve(ecu, request.setup);  // keeps --dt's value
    if (request_.bus == "loopback") {
      // Nothing else can send on a bus that lives in this process: the node would wait forever.
      throw UsageError(
          "--bus loopback: ecu would wait forever, as no other program can send on the "
          "in-process loopback bus; use replay --bus loopback, or ecu --bus vcan0 with play or "
          "canplayer sending");
    }
    request.scalar = model.scalar;
    node_.apply(request);
    if (model.scene_dt_s() > 0.0 && !given(ecu, "--dt"))
      request.setup.params.dt_s = model.scene_dt_s();
    const StopOnSignals signals(timeout_s_);
    request.stop = &stop_requested;
    std::function<void(std::uint64_t, std::uint64_t)> progress = make_frame_progress(
        err, "ecu", progress_ || stderr_is_terminal(err),
        fmt::format(
            "ecu: waiting for SeatInput frames on {} until {}{}SIGINT or SIGTERM", request.bus,
            request.max_frames > 0 ? fmt::format("{} frames, ", request.max_frames) : std::string(),
            timeout_s_ > 0.0 ? fmt::format("{} s, ", timeout_s_) : std::string()));
    request.progress = bus_progress(progress);
    const EcuResult result = run_ecu(request);
    out << fault_counters_text(result.faults) << "\n";
    if (!result.estimator_limits.empty()) out << "estimator: " << result.estimator_limits << "\n";
    out << result.json << "\n";
    return kExitOk;
  }

 private:
  EcuRequest request_;
  NodeOptions node_;
  double timeout_s_ = 0.0;
  bool progress_ = false;
  ModelOptions model_{kBusNodeChoices};
};

}  // namespace

std::unique_ptr<Command> make_replay_command() {
  return std::make_unique<ReplayCommand>();
}

std::unique_ptr<Command> make_ecu_command() {
  return std::make_unique<EcuCommand>();
}

}  // namespace stickslip::host
