// The CAN commands as functions (cli.cpp only parses options into these requests):
//   replay  a recording (CSV or candump log) streamed as frames over a bus to an ECU node,
//   ecu     the ECU node alone on a bus, for use with external tools,
//   record  a CSV recording written as a candump log of SeatInput frames (for canplayer).
#pragma once

#include <csignal>
#include <cstdint>
#include <string>
#include <vector>

#include "stickslip/can/receive_checker.hpp"
#include "stickslip/host/bus/ecu_node.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::host {

// The frames a recording becomes on the bus, with the time line the node's rows are written on.
struct BusRecording {
  std::vector<can::Frame> frames;  // in sending order
  std::vector<double> t_s;         // time of sample n (CSV: the file's t; log: n * dt)
  double dt_s = 0.0;               // the node's sample interval
  std::uint64_t saturated = 0;     // samples clipped by the encoder (CSV input)
  std::string recording_note;      // what reading did to the samples (recording_source.hpp)
  // A log's own time stamp (us since its epoch) and interface of every frame; empty for a CSV.
  std::vector<LoggedFrame> logged;
  // Where dt_s came from: "log" (its SeatInput time stamps), "--dt" (given, and the log agrees
  // or shows no rate), "csv" (the file's t column).
  std::string dt_source = "csv";
};

// How far a log's rate may be from --dt (relative) and still be the same rate: 1 %, room for
// a sender clock that is off by a little and for 1 us time stamps at up to 10 kHz.
inline constexpr double kLogRateTolerance = 0.01;

// The sample interval a log's SeatInput frames show: the median of the intervals between
// consecutive ones (robust to jitter and to a few lost frames), in s; 0 when there are fewer
// than two or their time stamps do not advance.
double log_sample_interval_s(const std::vector<LoggedFrame>& logged);

// The interval the node runs a log at. With a rate in the log: --dt when given and within
// kLogRateTolerance of it (UsageError naming both when not), else the log's. Without: --dt.
struct LogInterval {
  double dt_s;
  const char* source;  // "log" or "--dt"
};
LogInterval choose_log_interval(const std::string& path, double log_interval_s, double dt_s,
                                bool dt_given);

// A recording as simulate reads it (recording_source.hpp): one SeatInput frame per sample,
// counter = n mod 2^16. `command` (replay, play, record) is named where --gaps split is refused.
BusRecording frames_from_csv(const std::string& path, const RecordingOptions& recording = {},
                             const char* command = "replay");
// A rig recording (rig_recording.hpp: t, a_u, a_x[, x_r]) as the sensors and the floor would send
// it to a node running the estimator: per sample a SeatSensors frame (a_x, and x_r or not
// available), then the SeatInput frame; `saturated` counts samples with a clipped signal.
BusRecording frames_from_rig(const std::string& path);
// candump log (by read_candump_log): every frame as logged, whatever it is; the interval by
// choose_log_interval(), or dt_s when `log_times` is false (time stamps that are not the
// stream's: a capture of a stream played faster than real time).
BusRecording frames_from_log(const std::string& path, double dt_s, bool dt_given = false,
                             bool log_times = true);
// By extension: ".log" without --dbc is a candump log of SeatInput frames, anything else a
// recording as simulate reads it.
BusRecording read_bus_recording(const std::string& path, double log_dt_s,
                                const RecordingOptions& recording = {}, bool dt_given = false,
                                bool log_times = true, const char* command = "replay");

// Microseconds since the Unix epoch now (CLOCK_REALTIME): where logs the tools write start.
std::uint64_t realtime_now_us();

// Called after every frame with the frames done so far and the total (0: open-ended, as ecu
// without --frames); the caller limits how often it prints. A plain function and its context,
// so that this header pulls in no <functional> (tests include it after CppUTest's `new`).
struct BusProgress {
  void (*report)(void* context, std::uint64_t done, std::uint64_t total) = nullptr;
  void* context = nullptr;
  explicit operator bool() const noexcept { return report != nullptr; }
  void operator()(std::uint64_t done, std::uint64_t total) const { report(context, done, total); }
};

struct ReplayRequest {
  std::string input_path;
  RecordingOptions recording;  // which signal of the input, its unit, gaps, the model's step
  std::string bus = "loopback";
  SimulationSetup setup;  // dt_s from the input
  ScalarType scalar = ScalarType::float64;
  bool realtime = false;  // false: as fast as the node consumes ("max")
  std::string output_path;
  std::string output_log_path;  // empty: none; else every frame on the bus as a candump log
  double log_dt_s = 1e-3;       // sample interval of a candump-log input
  bool log_dt_given = false;    // --dt (or a scene's rate) was given: a log must agree with it
  // false: a log runs at its own rate (choose_log_interval) and the output log keeps every
  // logged frame's own time stamp and interface (the node's outputs take those of the frame
  // they answer). true: the log's time stamps are not the stream's (a capture of a stream
  // played faster than real time): it runs at log_dt_s, and the frames are timed n * dt from
  // the start (CLOCK_REALTIME) on the bus's interface, as a CSV input always is.
  bool retime = false;
  unsigned output_every = 1;  // the node's output cycle (EcuNodeConfig)
  OutputSet outputs = OutputSet::full;
  can::CheckerConfig checker;
  // The input is a rig recording (frames_from_rig) and the node runs the state estimator on it
  // (EcuNodeConfig::estimator).
  bool estimator = false;
  int receive_timeout_ms = 1000;  // per frame: longer is counted as silence and the replay goes on
  BusProgress progress;           // empty: none
};

// The bits on the wire of the classic frames a run put on the bus (can/frame_bits.hpp); error
// and CAN FD frames are not counted.
struct BusLoad {
  std::uint64_t frames = 0;
  std::uint64_t bits_exact = 0;
  std::uint64_t bits_worst_case = 0;
  void add(const can::Frame& frame);
};

struct ReplayResult {
  std::string bus;
  std::string recording_note;  // what reading did to the samples, if anything
  SimulationSummary summary;
  can::FaultCounters faults;
  port::TransportCounters sender;
  port::TransportCounters node;
  std::uint64_t frames_sent = 0;
  std::uint64_t input_saturated = 0;
  std::uint64_t output_frames = 0;           // sent by the node
  std::uint64_t output_frames_received = 0;  // seen back by the sender
  BusLoad bus_load;                          // everything sent on the bus
  std::string stats_json;                    // one line: simulate's keys, then bus and faults
  std::string estimator_limits;  // --estimator: what it could not estimate (empty: nothing)
};

// Streams the recording over the bus to an EcuNode in this process (two endpoints on the same
// bus, in lock step: each frame is sent, then received and processed by the node), writes the
// node's samples as simulate would (same columns; a_u the decoded sample) atomically.
ReplayResult replay_file(const ReplayRequest& request);

struct EcuRequest {
  std::string bus;
  SimulationSetup setup;  // params.dt_s: the stream's sample interval
  ScalarType scalar = ScalarType::float64;
  // Stop after this many frames for the node (every received frame except other nodes'
  // SeatMotion/SeatForce/SeatStats/SeatScene outputs, which are ignored); 0: never.
  std::uint64_t max_frames = 0;
  std::string output_path;        // empty: no CSV
  std::string sample_index_path;  // empty: none; else n,sample,held for every row (NodeTrace)
  unsigned output_every = 1;      // the node's output cycle (EcuNodeConfig)
  OutputSet outputs = OutputSet::full;
  can::CheckerConfig checker;
  bool estimator = false;  // run the state estimator on SeatSensors (EcuNodeConfig::estimator)
  int poll_ms = 20;        // receive timeout between checks of `stop`
  // SocketCAN SO_RCVBUF in bytes (0: the kernel's default; the kernel doubles it, up to twice
  // net.core.rmem_max): room for a node that falls behind a fast stream (receive_drops).
  int receive_buffer_bytes = 0;
  const volatile std::sig_atomic_t* stop = nullptr;  // set by a signal handler to end the run
  BusProgress progress;                              // empty: none
};

struct EcuResult {
  SimulationSummary summary;
  can::FaultCounters faults;
  port::TransportCounters transport;
  std::uint64_t frames_received = 0;
  std::uint64_t output_frames = 0;
  std::uint64_t output_send_failures = 0;  // output frames the bus refused (e.g. while down)
  std::uint64_t bus_down = 0;              // times the interface went down (or away) under the node
  std::uint64_t left_after_stop = 0;  // 1: the frame that ended the drain after a stop (unused)
  std::string json;                   // one line
  // --estimator: what the estimator could not estimate on this run (empty: nothing missing).
  std::string estimator_limits;
};

// The node on a bus until stopped. The interface going down (ENETDOWN) does not end the run:
// it is counted (bus_down), the node keeps its state and its sequence check, and the samples
// missed meanwhile are the gap the first frame after it reports (lost or skipped). A deleted
// interface is opened again once it is back. Other receive failures throw HostError. When
// `stop` is set, the frames the kernel received for the node before it are still taken (up to
// 10^6; the first later one ends the run unused, left_after_stop), then the run ends.
EcuResult run_ecu(const EcuRequest& request);

// Writes n,sample,held for every row of the trace (the node's row, the sender's sample number,
// 1 for a held row).
void write_sample_index(const std::string& path, const NodeTrace& trace);

struct PlayRequest {
  std::string input_path;  // CSV (t,a_u) or candump log, as replay reads it
  RecordingOptions recording;
  std::string bus;
  double speed = 1.0;      // frame i goes out at i * dt / speed after the start
  double log_dt_s = 1e-3;  // sample interval of a candump-log input
  bool log_dt_given = false;
  const volatile std::sig_atomic_t* stop = nullptr;
  BusProgress progress;  // empty: none
};

struct PlayResult {
  std::string recording_note;   // what reading did to the samples, if anything
  std::uint64_t frames = 0;     // in the recording
  std::uint64_t attempted = 0;  // frames whose time came (all, unless stopped)
  std::uint64_t sent = 0;       // accepted by the bus
  std::uint64_t not_sent = 0;   // refused: interface_down + buffer_full + other_failures
  std::uint64_t interface_down = 0, buffer_full = 0, other_failures = 0;
  std::uint64_t first_not_sent = 0, last_not_sent = 0;  // frame indices (when not_sent > 0)
  double duration_s = 0.0;
  double max_late_s = 0.0;  // the most a frame went out after its time
  std::string json;         // one line
};

// Sends the recording's frames on the bus at `speed` times real time, without a node (the
// sender side of the load test; canplayer stops at the first refused frame, this goes on).
PlayResult play_file(const PlayRequest& request);

struct RecordRequest {
  std::string input_path;
  RecordingOptions recording;
  std::string output_path;
  std::string interface = "vcan0";
  // The log's first time stamp, s since the Unix epoch; negative: the wall clock
  // (CLOCK_REALTIME) when record starts. Frame n is at start + (t_n - t_0) of the CSV.
  double start_time_s = -1.0;
};

// Returns the number of frames written and sets `saturated` to the clipped samples.
std::uint64_t record_log(const RecordRequest& request, std::uint64_t& saturated,
                         std::string* recording_note = nullptr);

// Writes the node's trace as simulate writes its output: t from `t_s` (index beyond it:
// t_s[0] + index * dt_s), then a_u, x_r, v_r, a_x, f_f, stuck.
void write_node_trace(const std::string& path, const NodeTrace& trace,
                      const std::vector<double>& t_s, double dt_s);

}  // namespace stickslip::host
