// The host's ECU node: the node of lib/ (stickslip/can/ecu_node.hpp: receive checker, sample
// numbering and gap policy, output frames in the DBC's layout, the same code the firmware runs)
// around the same oscillator and statistics loop that `simulate` runs (simulation.hpp). This
// class adds what only the host has: the scalar and law chosen at run time, the observer's
// windows for SeatStats/SeatScene, the state estimator, the trace and the run's statistics. Fed
// one frame at a time by whoever owns the bus (replay, the `ecu` command, tests), so it never
// blocks and no input can make it stop or throw: a refused frame is counted and goes no further.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/ecu_node.hpp"
#include "stickslip/can/frame.hpp"
#include "stickslip/can/receive_checker.hpp"
#include "stickslip/can/sensor_receiver.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/observer/state_estimator_params.hpp"

namespace stickslip::host {

// The messages the node publishes: full, reduced or motion (lib/can/ecu_node.hpp).
using OutputSet = can::OutputSet;

struct EcuNodeConfig {
  SimulationSetup setup;  // params (dt_s = the sample interval of the stream), x0, v0
  ScalarType scalar = ScalarType::float64;
  can::CheckerConfig checker;
  unsigned stats_every = 10;  // SeatStats/SeatScene every this many samples (>= 1)
  unsigned output_every = 1;  // SeatMotion/SeatForce every this many samples (>= 1)
  OutputSet outputs = OutputSet::full;
  bool keep_trace = true;  // store every sample (rows) for a CSV; off for an endless ecu run
  // Run the state estimator (observer/state_estimator.hpp) on SeatInput and SeatSensors and
  // publish SeatEstimate (and SeatEstimateForce with the full set) every output cycle and
  // FrictionEstimate every stats cycle. Double, or float with --scalar float; not fixed point.
  bool estimator = false;
};

// The estimator's parameters for the node's seat: mass, k, b and the start values of F_fk and
// F_fs from the model parameters (F_fs at least F_fk), the sample interval, the rest defaults.
StateEstimatorParams node_estimator_params(const OscillatorParams& params);

// When a friction estimate is published (not available before): the start value's weight in the
// exponential average has fallen to e^-3 (5 %): 3 averaging times of slip samples for F_fk,
// ceil(3 / -ln(1 - w)) break-aways for F_fs (w the weight of one).
bool kinetic_friction_converged(const StateEstimatorParams& params, std::uint64_t kinetic_samples);
bool static_friction_converged(const StateEstimatorParams& params, std::uint32_t breakaways);

// The state estimator's view of the run (EcuNode::estimator_report()).
struct EstimatorReport {
  can::SensorCounters sensors;
  double x_r_m = 0.0, v_r_m_per_s = 0.0, friction_n = 0.0;
  double kinetic_friction_n = 0.0, static_friction_n = 0.0, bias_m_per_s2 = 0.0;
  bool kinetic_converged = false, static_converged = false;
  std::uint32_t breakaways = 0;
  std::uint64_t kinetic_samples = 0;
};

// What the estimator could not estimate on this run, from the sensors it was given (one
// sentence; empty when a_x and travel came with the samples).
std::string estimator_limits(const can::SensorCounters& sensors, std::uint64_t samples);

// One output sample of the node, as simulate writes it (double holds a float run exactly).
struct NodeTrace {
  std::vector<std::uint64_t> index;  // sample index since the first accepted frame
  // The sender's sample number of the row: the first accepted frame's 16-bit counter, then
  // advanced by every counter step (so it counts on past 2^16; a restarted sender steps back).
  // A held row has the number of the sample it stands in for.
  std::vector<std::int64_t> sample;
  std::vector<double> a_u, x_r, v_r, a_x, f_f;
  std::vector<std::uint8_t> stuck;
  std::vector<std::uint8_t> held;  // 1: filled in by the gap policy, not received
};

class SeatModel;  // the oscillator + statistics for the configured law and scalar (ecu_node.cpp)
class SeatEstimatorRun;  // the state estimator in the configured scalar (ecu_node.cpp)

// One sample of the seat in double (a float run exactly).
struct SampleOutput {
  double x_r, v_r, a_x, f_f;
  bool stuck;
};

// The host's seat as the lib node's Seat: SeatModel behind the word interface. a_u is decoded
// and the outputs quantised in double, as the host node always did (exact for double and float
// runs alike); the statistics words come from the observer's window.
class HostSeat {
 public:
  can::SeatWords start(std::uint16_t a_u_word);
  can::SeatWords step(std::uint16_t a_u_word);
  can::StatsWords statistics() const;

  SeatModel* model = nullptr;
  SampleOutput last{};  // the last sample, for the trace
};

class EcuNode {
 public:
  // Throws ConfigurationError when the core refuses the parameters.
  explicit EcuNode(const EcuNodeConfig& config);
  ~EcuNode();
  EcuNode(const EcuNode&) = delete;
  EcuNode& operator=(const EcuNode&) = delete;

  // Checks one received frame and, for an accepted one, steps the model for every sample it
  // brings (held samples for a gap first). Appends the output frames to `outputs`. `now_ns`:
  // any monotonic clock, for the silence timeout. Returns the verdict.
  can::FrameVerdict on_frame(const can::Frame& frame, std::uint64_t now_ns,
                             std::vector<can::Frame>& outputs);
  // Call when the bus has been quiet (a receive timed out): counts bus silence.
  void on_idle(std::uint64_t now_ns) { node_.on_idle(now_ns); }
  // Restarts the silence clock (call once when the node starts listening).
  void start(std::uint64_t now_ns) { node_.start(now_ns); }

  const can::FaultCounters& counters() const noexcept { return node_.counters(); }
  // Frames with the SeatInput identifier checked so far (whatever their verdict).
  std::uint64_t input_frames() const noexcept { return node_.input_frames(); }
  std::uint64_t samples() const noexcept { return node_.samples(); }
  // The sender's sample numbers (see NodeTrace::sample) of the first and the last row; valid
  // when samples() > 0. A restarted node starts again at the counter of its first frame: the
  // samples before it that it never saw are the gap across the restart.
  std::int64_t first_sample() const noexcept { return node_.first_sample(); }
  std::int64_t last_sample() const noexcept { return node_.last_sample(); }
  const NodeTrace& trace() const noexcept { return trace_; }
  // The statistics of the run so far, as simulate_signal() reports them (ns_per_sample: wall
  // time of on_frame per sample, not comparable with simulate's tight loop).
  SimulationSummary summary() const;
  // The estimator's counters and last estimate (config.estimator only).
  bool estimator() const noexcept { return config_.estimator; }
  EstimatorReport estimator_report() const;

 private:
  struct Sink;  // the lib node's frames into `outputs`, its samples into record()
  // After the lib node has published one sample: the trace and the estimator.
  void record(const can::NodeSample& sample, std::vector<can::Frame>& outputs);
  void estimate(double a_u, bool held, bool resync, std::int64_t sample, std::uint64_t index,
                std::vector<can::Frame>& outputs);

  EcuNodeConfig config_;
  can::EcuNode<HostSeat> node_;
  std::unique_ptr<SeatModel> model_;
  std::unique_ptr<SeatEstimatorRun> estimator_;
  StateEstimatorParams estimator_params_;
  can::SensorReceiver sensors_;
  NodeTrace trace_;
  double busy_s_ = 0.0;
  std::uint8_t alive_[3] = {0, 0, 0};  // SeatEstimate, SeatEstimateForce, FrictionEstimate
};

// One output frame of `message` for sample `sample_counter`; advances the message's `alive`
// counter and sets the saturation flag when quantise() clipped a signal.
can::Frame output_frame(const can::MessageSpec& message, std::uint16_t sample_counter,
                        std::uint8_t& alive, std::uint8_t flags, double first, double second);

// The counters as one JSON object (one line) and as a short human summary.
std::string fault_counters_json(const can::FaultCounters& counters);
std::string fault_counters_text(const can::FaultCounters& counters);

}  // namespace stickslip::host
