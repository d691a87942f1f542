#include "stickslip/host/bus/ecu_node.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <limits>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/node_seats.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/host/run/fixed_dispatch.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/scaled_end_stops.hpp"
#include "stickslip/observer/observer.hpp"
#include "stickslip/observer/state_estimator.hpp"

namespace stickslip::host {

// The model behind one virtual call per sample: the loop body of simulate_signal() (reset and
// current() for the first sample, step() after), with the statistics in the run's scalar type.
class SeatModel {
 public:
  virtual ~SeatModel() = default;
  // The SeatInput a_u word of the sample.
  virtual SampleOutput first(std::uint16_t a_u_word) = 0;
  virtual SampleOutput step(std::uint16_t a_u_word) = 0;
  // The SeatMotion/SeatForce words of the last sample: quantised in double (exact for double and
  // float runs alike), unless the model has words of its own.
  virtual can::SeatWords words(const SampleOutput& last) const {
    return can::SeatWords{can::quantise(can::kSeatMotion.signals[0], last.a_x),
                          can::quantise(can::kSeatMotion.signals[1], last.x_r),
                          can::quantise(can::kSeatForce.signals[0], last.v_r),
                          can::quantise(can::kSeatForce.signals[1], last.f_f), last.stuck};
  }
  virtual void summarise(SimulationSummary& summary) const = 0;
  // The SeatStats/SeatScene words the node publishes: the window's figures as of its last
  // completed block, or the whole stream's for a model without a window.
  virtual can::StatsWords statistics() const = 0;
};

// The state estimator behind one virtual call per sample, in the run's scalar (double or float:
// the decoded inputs are exact in both).
class SeatEstimatorRun {
 public:
  virtual ~SeatEstimatorRun() = default;
  virtual void reset(double a_u, double x0_m) = 0;
  virtual void step(double a_u, double a_x, double x_r) = 0;
  virtual StateEstimate<double> estimate() const = 0;
};

namespace {

double decoded(std::uint16_t a_u_word) {
  return can::physical<double>(can::kSeatInput.signals[0], a_u_word);
}

// The figures of a model without an observer: the whole stream so far, ready from the first
// sample.
ObserverSummary whole_stream_figures(const RunningStatistics<double>& statistics,
                                     const OscillatorParams& params, std::uint64_t samples) {
  ObserverSummary o;
  o.rms_u_m_per_s2 = statistics.rms_u();
  o.rms_x_m_per_s2 = statistics.rms_x();
  o.transmissibility = statistics.transmissibility();
  o.stick_probability = statistics.stick_probability();
  o.den_hartog_k = den_hartog_factor(params.kinetic_friction_n, params.mass_kg, o.rms_u_m_per_s2);
  o.window_s = static_cast<double>(samples) * params.dt_s;
  return o;
}

can::StatsWords stats_words_of(const ObserverSummary& o) {
  return can::stats_words(o.window_s > 0.0, o.transmissibility, o.stick_probability,
                          o.den_hartog_k);
}

template <typename T>
class SeatEstimatorFor final : public SeatEstimatorRun {
 public:
  explicit SeatEstimatorFor(const StateEstimatorParams& params) {
    const ConfigResult configured = estimator_.configure(params);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  }
  void reset(double a_u, double x0_m) override {
    estimator_.reset(static_cast<T>(a_u), static_cast<T>(x0_m));
  }
  void step(double a_u, double a_x, double x_r) override {
    estimator_.step(static_cast<T>(a_u), static_cast<T>(a_x), static_cast<T>(x_r));
  }
  StateEstimate<double> estimate() const override {
    const StateEstimate<T>& e = estimator_.estimate();
    StateEstimate<double> out;
    out.x_r_m = static_cast<double>(e.x_r_m);
    out.v_r_m_per_s = static_cast<double>(e.v_r_m_per_s);
    out.friction_n = static_cast<double>(e.friction_n);
    out.kinetic_friction_n = static_cast<double>(e.kinetic_friction_n);
    out.static_friction_n = static_cast<double>(e.static_friction_n);
    out.bias_m_per_s2 = static_cast<double>(e.bias_m_per_s2);
    out.relative_acceleration_m_per_s2 = static_cast<double>(e.relative_acceleration_m_per_s2);
    out.stuck = e.stuck;
    out.breakaways = e.breakaways;
    out.kinetic_samples = e.kinetic_samples;
    return out;
  }

 private:
  StateEstimator<T> estimator_;
};

// kEndStops: the seat with end stops (setup.stops), as simulate runs it.
template <typename T, typename Law, bool kEndStops = false>
class SeatModelFor final : public SeatModel {
 public:
  SeatModelFor(const SimulationSetup& setup)
      : x0_(static_cast<T>(setup.x0_m)), v0_(static_cast<T>(setup.v0_m_per_s)) {
    ObserverParams params = can::seat_observer_params(setup.params);
    params.stops = setup.stops;
    const ConfigResult configured = observer_.configure(params);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    statistics_.reset();
  }

  SampleOutput first(std::uint16_t a_u_word) override {
    const T input = static_cast<T>(decoded(a_u_word));
    observer_.reset(input, x0_, v0_);
    statistics_.reset();
    events_ = 0;
    const StepOutput<T> out = observer_.estimate().model;
    statistics_.add_sample(input, out.a_x_m_per_s2);
    return convert(out);
  }

  can::StatsWords statistics() const override { return stats_words_of(observer_.summary()); }

  SampleOutput step(std::uint16_t a_u_word) override {
    const T input = static_cast<T>(decoded(a_u_word));
    // The observer's estimate is the oscillator's step, bit for bit (tests/core/test_observer.cpp).
    const StepOutput<T> out = observer_.update(input).model;
    statistics_.add_sample(input, out.a_x_m_per_s2);
    statistics_.add_step(out.stuck_fraction);
    events_ += out.events;
    return convert(out);
  }

  void summarise(SimulationSummary& summary) const override {
    summarise_run(summary, statistics_, observer_.model(), events_);
    summarise_comfort(summary, observer_.comfort());
    const ObserverSummary o = observer_.summary();
    summary.observed = true;
    summary.window_s = o.window_s;
    summary.window_transmissibility = o.transmissibility;
    summary.window_stick_probability = o.stick_probability;
    summary.window_den_hartog_k = o.den_hartog_k;
    summary.window_stick_events = o.stick_events;
    summary.window_slip_events = o.slip_events;
    summary.regime_changes = o.regime_changes;
    summary.observer_regime =
        o.regime_known ? regime_name(o.regime) : "unknown (window not yet full)";
  }

 private:
  static SampleOutput convert(const StepOutput<T>& out) {
    return {static_cast<double>(out.x_r_m), static_cast<double>(out.v_r_m_per_s),
            static_cast<double>(out.a_x_m_per_s2), static_cast<double>(out.friction_n), out.stuck};
  }

  // The model, its windows, regime and ride comfort.
  Observer<T, Law, can::kSeatWindowBlocks, true, kEndStops> observer_;
  RunningStatistics<T> statistics_;
  std::uint64_t events_ = 0;
  T x0_, v0_;
};

// Fixed point (Q23.40): the loop body of simulate_signal_fixed() (the input converted as an ECU
// converts it, statistics in double) on the model with_fixed_scene_model() chooses, so with end
// stops too. No observer (its windows and filters run in float or double): the published T_ax, p
// and K are those of the whole stream so far.
template <typename Model>
class SeatModelFixed final : public SeatModel {
 public:
  explicit SeatModelFixed(const SimulationSetup& setup)
      : setup_(setup), x0_(setup.x0_m), v0_(setup.v0_m_per_s) {
    const ConfigResult configured =
        configure_for_scene(oscillator_, SceneParams{setup.effects, setup.params, setup.stops});
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  }
  SampleOutput first(std::uint16_t a_u_word) override {
    const Fixed input(decoded(a_u_word));
    start_saturated_ = take_fixed_point_saturation();
    oscillator_.reset(x0_, v0_, input);
    statistics_.reset();
    events_ = 0;
    samples_ = 1;
    const StepOutput<Fixed> out = oscillator_.current();
    statistics_.add_sample(input.to_double(), out.a_x_m_per_s2.to_double());
    return convert(out);
  }
  SampleOutput step(std::uint16_t a_u_word) override {
    const Fixed input(decoded(a_u_word));
    const StepOutput<Fixed> out = oscillator_.step(input);
    ++samples_;
    statistics_.add_sample(input.to_double(), out.a_x_m_per_s2.to_double());
    statistics_.add_step(out.stuck_fraction.to_double());
    events_ += out.events;
    return convert(out);
  }
  void summarise(SimulationSummary& summary) const override {
    summarise_run(summary, statistics_, oscillator_, events_);
    summary.saturated_steps = oscillator_.saturated_steps() + (start_saturated_ ? 1u : 0u);
  }
  can::StatsWords statistics() const override {
    return stats_words_of(whole_stream_figures(statistics_, setup_.params, samples_));
  }

 private:
  static SampleOutput convert(const StepOutput<Fixed>& out) {
    return {out.x_r_m.to_double(), out.v_r_m_per_s.to_double(), out.a_x_m_per_s2.to_double(),
            out.friction_n.to_double(), out.stuck};
  }
  SimulationSetup setup_;
  Model oscillator_;
  RunningStatistics<double> statistics_;
  std::uint64_t events_ = 0;
  std::uint64_t samples_ = 0;
  Fixed x0_, v0_;
  bool start_saturated_ = false;
};

std::unique_ptr<SeatModel> make_fixed_model(const SimulationSetup& setup) {
  const SceneParams scene{setup.effects, setup.params, setup.stops};
  return with_fixed_scene_model(scene, [&](auto& model) -> std::unique_ptr<SeatModel> {
    return std::make_unique<SeatModelFixed<std::decay_t<decltype(model)>>>(setup);
  });
}

// Q7.24 in scene units: the Cortex-M0+ firmware's seat (can::ScaledSeat, node_seats.hpp), its
// input and output words by its integer scales, and T_ax, p and K from its window over those
// words, so the node sends the firmware's frames; with end stops the same seat around the model
// with stops in scene units (ScaledEndStopOscillator). The trace and the run's statistics in SI
// (double).
template <typename Seat>
class SeatModelFixed32 final : public SeatModel {
 public:
  explicit SeatModelFixed32(const SimulationSetup& setup) {
    ConfigResult configured;
    if constexpr (kHasEndStops<std::decay_t<decltype(seat_.model().oscillator())>>) {
      configured = seat_.configure(setup.params, setup.stops);
    } else {
      configured = seat_.configure(setup.params);
    }
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    if (setup.x0_m != 0.0 || setup.v0_m_per_s != 0.0)
      throw UsageError("--scalar fixed32: the ECU node's seat starts at rest (x0 = v0 = 0)");
    units_ = seat_.model().units();
  }
  SampleOutput first(std::uint16_t a_u_word) override {
    words_ = seat_.start(a_u_word);
    statistics_.reset();
    events_ = 0;
    const SampleOutput out = convert(seat_.last());
    statistics_.add_sample(decoded(a_u_word), out.a_x);
    return out;
  }
  SampleOutput step(std::uint16_t a_u_word) override {
    words_ = seat_.step(a_u_word);
    const StepOutput<Fixed32>& out = seat_.last();
    const SampleOutput converted = convert(out);
    statistics_.add_sample(decoded(a_u_word), converted.a_x);
    statistics_.add_step(out.stuck_fraction.to_double());
    events_ += out.events;
    return converted;
  }
  can::SeatWords words(const SampleOutput& /*last*/) const override { return words_; }
  void summarise(SimulationSummary& summary) const override {
    summarise_run(summary, statistics_, seat_.model().oscillator(), events_);
    summary.saturated_steps = seat_.model().oscillator().saturated_steps();
  }
  // The firmware's window over its words (can::WordWindow).
  can::StatsWords statistics() const override { return seat_.statistics(); }

 private:
  SampleOutput convert(const StepOutput<Fixed32>& out) const {
    return {out.x_r_m.to_double() * units_.length_m,
            out.v_r_m_per_s.to_double() * units_.velocity_m_per_s(),
            out.a_x_m_per_s2.to_double() * units_.acceleration_m_per_s2(),
            out.friction_n.to_double() * units_.force_n(), out.stuck};
  }
  Seat seat_;
  SceneUnits units_;
  can::SeatWords words_;
  RunningStatistics<double> statistics_;
  std::uint64_t events_ = 0;
};

template <typename Law>
using Fixed32NodeSeat = can::ScaledSeat<Fixed32, Law>;
template <typename Law>
using Fixed32NodeSeatWithStops =
    can::ScaledSeat<Fixed32, Law, ScaledEndStopOscillator<Fixed32, Law>>;

std::unique_ptr<SeatModel> make_fixed32_model(const SimulationSetup& setup) {
  if (setup.effects & kEndStops) {
    // No friction, or Coulomb stick-slip, whose configure() refuses any other model by name.
    if (setup.params.model == FrictionModel::linear)
      return std::make_unique<SeatModelFixed32<Fixed32NodeSeatWithStops<NoFriction>>>(setup);
    return std::make_unique<SeatModelFixed32<Fixed32NodeSeatWithStops<CoulombStickSlip>>>(setup);
  }
  return with_fixed_law<Fixed32NodeSeat>(
      setup.params, [&](auto& seat) -> std::unique_ptr<SeatModel> {
        return std::make_unique<SeatModelFixed32<std::decay_t<decltype(seat)>>>(setup);
      });
}

template <typename T>
std::unique_ptr<SeatModel> make_model(const SimulationSetup& setup) {
  if (setup.effects & kEndStops) {  // the scene's model (models/scene.hpp)
    if (setup.params.model == FrictionModel::linear)
      return std::make_unique<SeatModelFor<T, NoFriction, true>>(setup);
    if (setup.params.model == FrictionModel::stribeck)
      return std::make_unique<SeatModelFor<T, StribeckStickSlip, true>>(setup);
    return std::make_unique<SeatModelFor<T, CoulombStickSlip, true>>(setup);
  }
  // The same law for the same parameters as with_oscillator() (dispatch.hpp) chooses.
  return with_oscillator<T>(setup.params, [&](auto& oscillator) -> std::unique_ptr<SeatModel> {
    using Osc = std::decay_t<decltype(oscillator)>;
    return std::make_unique<SeatModelFor<T, typename Osc::FrictionLaw>>(setup);
  });
}

std::uint64_t clock_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

}  // namespace

StateEstimatorParams node_estimator_params(const OscillatorParams& params) {
  StateEstimatorParams p;
  p.mass_kg = params.mass_kg;
  p.stiffness_n_per_m = params.stiffness_n_per_m;
  p.damping_ns_per_m = params.damping_ns_per_m;
  p.initial_kinetic_friction_n = params.kinetic_friction_n;
  p.initial_static_friction_n = std::fmax(params.static_friction_n, params.kinetic_friction_n);
  p.dt_s = params.dt_s;
  return p;
}

bool kinetic_friction_converged(const StateEstimatorParams& params, std::uint64_t kinetic_samples) {
  return static_cast<double>(kinetic_samples) * params.dt_s >= 3.0 * params.kinetic_friction_time_s;
}

bool static_friction_converged(const StateEstimatorParams& params, std::uint32_t breakaways) {
  const double w = params.static_friction_weight;
  const double needed = w >= 1.0 ? 1.0 : std::ceil(3.0 / -std::log1p(-w));
  return static_cast<double>(breakaways) >= needed;
}

std::string estimator_limits(const can::SensorCounters& sensors, std::uint64_t samples) {
  if (samples == 0) return "no samples: nothing estimated";
  if (sensors.with_a_x == 0 && sensors.with_travel == 0) {
    return "no SeatSensors samples (a_x, x_r): the estimator runs the model open loop from its "
           "start values; x_r, v_r and F_f are the model's, F_fk and F_fs are not estimated "
           "(FrictionEstimate sends not available)";
  }
  if (sensors.with_a_x == 0) {
    return "no seat acceleration a_x: F_fk and F_fs are not learnt (FrictionEstimate sends not "
           "available); v_r and F_f are right only where the start values are the seat's "
           "friction";
  }
  if (sensors.with_travel == 0) {
    return "no travel x_r: x_r's offset is not observable (bounded by the stick band F_fs/k, a "
           "few tenths of a mm); v_r, F_f, F_fk and F_fs are estimated";
  }
  return {};
}

can::SeatWords HostSeat::start(std::uint16_t a_u_word) {
  last = model->first(a_u_word);
  return model->words(last);
}

can::SeatWords HostSeat::step(std::uint16_t a_u_word) {
  last = model->step(a_u_word);
  return model->words(last);
}

can::StatsWords HostSeat::statistics() const {
  return model->statistics();
}

struct EcuNode::Sink {
  EcuNode& node;
  std::vector<can::Frame>& outputs;
  void send(const can::Frame& frame) { outputs.push_back(frame); }
  void sampled(const can::NodeSample& sample) { node.record(sample, outputs); }
};

EcuNode::EcuNode(const EcuNodeConfig& config) : config_(config) {
  if (config_.stats_every == 0) config_.stats_every = 1;
  if (config_.output_every == 0) throw UsageError("--output-every: must be >= 1 sample");
  if (config_.setup.reference) throw UsageError("the ECU node runs the core's integrators only");
  if (config_.estimator &&
      (config_.scalar == ScalarType::fixed || config_.scalar == ScalarType::fixed32))
    throw UsageError(
        "--estimator: runs in double or float only (its covariance spans 1e-16 .. 1e2, which no "
        "Q format holds); use --scalar double or float");
  switch (config_.scalar) {
    case ScalarType::fixed:
      model_ = make_fixed_model(config_.setup);
      break;
    case ScalarType::fixed32:
      model_ = make_fixed32_model(config_.setup);
      break;
    case ScalarType::float32:
      model_ = make_model<float>(config_.setup);
      break;
    default:
      model_ = make_model<double>(config_.setup);
  }
  node_.seat().model = model_.get();
  can::EcuNodeParams node_params;
  node_params.checker = config_.checker;
  node_params.stats_every = config_.stats_every;
  node_params.output_every = config_.output_every;
  node_params.outputs = config_.outputs;
  if (node_.configure(node_params) != Status::ok)
    throw UsageError("the ECU node refused its output and stats cycles");
  if (config_.estimator) {
    if (config_.setup.effects & kEndStops)
      throw UsageError(
          "--estimator: the state estimator models the seat without end stops, so its estimates "
          "would be wrong in contact; drop the end stops from the scene or the --estimator");
    estimator_params_ = node_estimator_params(config_.setup.params);
    if (config_.scalar == ScalarType::float32) {
      estimator_ = std::make_unique<SeatEstimatorFor<float>>(estimator_params_);
    } else {
      estimator_ = std::make_unique<SeatEstimatorFor<double>>(estimator_params_);
    }
  }
}

EcuNode::~EcuNode() = default;

can::FrameVerdict EcuNode::on_frame(const can::Frame& frame, std::uint64_t now_ns,
                                    std::vector<can::Frame>& outputs) {
  const std::uint64_t start = clock_ns();
  if (estimator_ && frame.id == can::kSeatSensors.id) {
    // Kept for the SeatInput sample with its counter (sensor_receiver.hpp); no sample by itself.
    const can::SensorVerdict verdict = sensors_.take(frame);
    if (verdict != can::SensorVerdict::not_sensors) {
      busy_s_ += static_cast<double>(clock_ns() - start) * 1e-9;
      switch (verdict) {
        case can::SensorVerdict::accepted:
          return can::FrameVerdict::accepted;
        case can::SensorVerdict::wrong_length:
          return can::FrameVerdict::wrong_length;
        case can::SensorVerdict::bad_crc:
          return can::FrameVerdict::bad_crc;
        case can::SensorVerdict::duplicate:
          return can::FrameVerdict::duplicate;
        default:
          return can::FrameVerdict::alive_mismatch;
      }
    }
  }
  Sink sink{*this, outputs};
  const can::FrameVerdict verdict = node_.on_frame(frame, now_ns, sink);
  busy_s_ += static_cast<double>(clock_ns() - start) * 1e-9;
  return verdict;
}

void EcuNode::record(const can::NodeSample& sample, std::vector<can::Frame>& outputs) {
  const double a_u = can::physical<double>(can::kSeatInput.signals[0], sample.a_u_word);
  if (config_.keep_trace) {
    const SampleOutput& out = node_.seat().last;
    trace_.index.push_back(sample.index);
    trace_.sample.push_back(sample.sample);
    trace_.a_u.push_back(a_u);
    trace_.x_r.push_back(out.x_r);
    trace_.v_r.push_back(out.v_r);
    trace_.a_x.push_back(out.a_x);
    trace_.f_f.push_back(out.f_f);
    trace_.stuck.push_back(out.stuck ? 1 : 0);
    trace_.held.push_back(sample.held ? 1 : 0);
  }
  if (estimator_) estimate(a_u, sample.held, sample.resync, sample.sample, sample.index, outputs);
}

void EcuNode::estimate(double a_u, bool held, bool resync, std::int64_t sample, std::uint64_t index,
                       std::vector<can::Frame>& outputs) {
  // The sensors measured at this sample (a held sample's too: only its SeatInput was lost).
  double a_x = 0.0, x_r = 0.0;
  sensors_.sample(static_cast<std::uint16_t>(static_cast<std::uint64_t>(sample) & 0xFFFFu), a_x,
                  x_r);
  if (index == 0) {
    // Parked where the travel sensor says (the setup's x0 without one), as the model starts.
    estimator_->reset(a_u, std::isfinite(x_r) ? x_r : config_.setup.x0_m);
  } else {
    estimator_->step(a_u, a_x, x_r);
  }
  const StateEstimate<double> e = estimator_->estimate();
  const auto counter = static_cast<std::uint16_t>(index & 0xFFFFu);
  const std::uint8_t state_flags = static_cast<std::uint8_t>(
      (e.stuck ? can::kStuck : 0) | (held ? can::kHeld : 0) | (resync ? can::kResync : 0));
  const bool reduced = config_.outputs == OutputSet::reduced;
  if (index % config_.output_every == 0) {
    outputs.push_back(
        output_frame(can::kSeatEstimate, counter, alive_[0], state_flags, e.x_r_m, e.v_r_m_per_s));
    if (!reduced)
      outputs.push_back(output_frame(can::kSeatEstimateForce, counter, alive_[1], state_flags,
                                     e.friction_n, e.bias_m_per_s2));
  }
  if (index % config_.stats_every == 0) {
    // Not available (all ones, J1939 style) until the start value has lost its weight.
    const double not_available = std::numeric_limits<double>::quiet_NaN();
    outputs.push_back(output_frame(
        can::kFrictionEstimate, counter, alive_[2], 0,
        kinetic_friction_converged(estimator_params_, e.kinetic_samples) ? e.kinetic_friction_n
                                                                         : not_available,
        static_friction_converged(estimator_params_, e.breakaways) ? e.static_friction_n
                                                                   : not_available));
  }
}

EstimatorReport EcuNode::estimator_report() const {
  EstimatorReport report;
  report.sensors = sensors_.counters();
  if (!estimator_ || node_.samples() == 0) return report;
  const StateEstimate<double> e = estimator_->estimate();
  report.x_r_m = e.x_r_m;
  report.v_r_m_per_s = e.v_r_m_per_s;
  report.friction_n = e.friction_n;
  report.kinetic_friction_n = e.kinetic_friction_n;
  report.static_friction_n = e.static_friction_n;
  report.bias_m_per_s2 = e.bias_m_per_s2;
  report.kinetic_converged = kinetic_friction_converged(estimator_params_, e.kinetic_samples);
  report.static_converged = static_friction_converged(estimator_params_, e.breakaways);
  report.breakaways = e.breakaways;
  report.kinetic_samples = e.kinetic_samples;
  return report;
}

can::Frame output_frame(const can::MessageSpec& message, std::uint16_t sample_counter,
                        std::uint8_t& alive, std::uint8_t flags, double first, double second) {
  const can::Quantised q0 = can::quantise(message.signals[0], first);
  const can::Quantised q1 = can::quantise(message.signals[1], second);
  can::Payload payload;
  payload.sample_counter = sample_counter;
  payload.alive_counter = alive;
  alive = static_cast<std::uint8_t>((alive + 1u) & 0x0Fu);
  payload.flags =
      static_cast<std::uint8_t>(flags | ((q0.saturated || q1.saturated) ? can::kSaturated : 0));
  payload.words[0] = q0.word;
  payload.words[1] = q1.word;
  return can::make_frame(message, payload);
}

SimulationSummary EcuNode::summary() const {
  SimulationSummary summary;
  summary.dt_s = config_.setup.params.dt_s;
  summary.end_stops = (config_.setup.effects & kEndStops) != 0;  // contacts 0 before a sample
  const std::uint64_t samples = node_.samples();
  if (samples > 0) model_->summarise(summary);
  summary.den_hartog_k = den_hartog_factor(config_.setup.params.kinetic_friction_n,
                                           config_.setup.params.mass_kg, summary.rms_u);
  summary.repetitions = 1;
  summary.ns_per_sample = samples > 1 ? busy_s_ * 1e9 / static_cast<double>(samples - 1) : 0.0;
  return summary;
}

namespace {

template <typename Fn>
void for_each_counter(const can::FaultCounters& c, Fn&& fn) {
  fn("frames", c.frames);
  fn("accepted", c.accepted);
  fn("ignored_output", c.ignored_output);
  fn("lost", c.lost);
  fn("duplicate", c.duplicate);
  fn("out_of_order", c.out_of_order);
  fn("bad_crc", c.bad_crc);
  fn("wrong_length", c.wrong_length);
  fn("foreign_frames", c.foreign_frames);
  fn("can_fd", c.can_fd);
  fn("error_frame", c.error_frame);
  fn("remote_frame", c.remote_frame);
  fn("alive_mismatch", c.alive_mismatch);
  fn("invalid_signal", c.invalid_signal);
  fn("resync", c.resync);
  fn("skipped", c.skipped);
  fn("silence", c.silence);
  fn("held_samples", c.held_samples);
  fn("sender_saturated", c.sender_saturated);
}

}  // namespace

std::string fault_counters_json(const can::FaultCounters& counters) {
  nlohmann::ordered_json json;
  for_each_counter(counters, [&](const char* name, std::uint64_t value) { json[name] = value; });
  json["faults"] = counters.faults();
  return json.dump();
}

std::string fault_counters_text(const can::FaultCounters& counters) {
  std::string text = fmt::format("faults {}:", counters.faults());
  for_each_counter(counters, [&](const char* name, std::uint64_t value) {
    text += fmt::format(" {} {}", name, value);
  });
  return text;
}

}  // namespace stickslip::host
