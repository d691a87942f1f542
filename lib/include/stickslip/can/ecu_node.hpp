// The ECU node: one SeatInput frame in -> the receive checker (receive_checker.hpp) -> a seat
// step for every sample the frame brings (held samples for a gap first) -> the output frames of
// docs/can/stickslip.dbc. One source for the host (`stickslip ecu` and `replay`, which add I/O,
// options and statistics around it) and for the Cortex-M firmware (port/baremetal/src/node.cpp).
// Allocation-free, noexcept, standard headers only; no clock: the caller passes the time.
//
// The seat is a template parameter (node_seats.hpp has the ones lib/ offers), so the node runs
// any scalar: it hands the seat the raw a_u word and takes back the words to send. A Seat has
//   SeatWords start(std::uint16_t a_u_word) noexcept;  // the first sample: reset, no step
//   SeatWords step(std::uint16_t a_u_word) noexcept;   // every further sample
//   StatsWords statistics() const noexcept;            // for SeatStats/SeatScene
// The caller's Sink takes what the node produces, in order:
//   void send(const Frame& frame);           // one output frame
//   void sampled(const NodeSample& sample);  // after the frames of each sample
#pragma once

#include <cmath>
#include <cstdint>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/frame.hpp"
#include "stickslip/can/receive_checker.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip::can {

// The messages the node publishes (docs/CAN.md, "Bus load"):
//   full:    SeatMotion and SeatForce every output cycle, SeatStats and SeatScene every stats
//            cycle;
//   reduced: SeatMotion and SeatStats only, for 250 and 500 kbit/s buses;
//   motion:  SeatMotion and SeatForce only, for a node without running statistics or a bus
//            without room for them.
enum class OutputSet : std::uint8_t { full, reduced, motion };

// A seat's outputs for one sample as the words SeatMotion and SeatForce carry.
struct SeatWords {
  Quantised a_x, x_r, v_r, f_f;
  bool stuck = false;
};

// The running statistics as the words SeatStats and SeatScene carry (not available until known).
struct StatsWords {
  Quantised transmissibility{kUnsignedNotAvailable, false};
  Quantised stick_probability{kUnsignedNotAvailable, false};
  Quantised den_hartog_k{kUnsignedNotAvailable, false};
};

// The window figures T_ax, p and K as the SeatStats/SeatScene words: not available (all ones, as
// J1939 does) until they are `ready` (a first block has completed), and K also while it is not
// finite. R: float or double; a float figure gives the word its value in double gives (the
// scaling is a power of two, exact in both).
template <typename R>
StatsWords stats_words(bool ready, R transmissibility, R stick_probability, R k) noexcept {
  const R not_available = R(NAN);
  StatsWords words;
  words.transmissibility =
      quantise(kSeatStats.signals[0], ready ? transmissibility : not_available);
  words.stick_probability =
      quantise(kSeatStats.signals[1], ready ? stick_probability : not_available);
  words.den_hartog_k =
      quantise(kSeatScene.signals[0], ready && std::isfinite(k) ? k : not_available);
  return words;
}

struct EcuNodeParams {
  CheckerConfig checker;
  unsigned stats_every = 10;  // SeatStats/SeatScene every this many samples (>= 1)
  unsigned output_every = 1;  // SeatMotion/SeatForce every this many samples (>= 1)
  OutputSet outputs = OutputSet::full;
};

// One sample the node has stepped, for the caller's record.
struct NodeSample {
  std::uint64_t index = 0;  // since the first accepted frame
  // The sender's sample number: the first accepted frame's 16-bit counter, then advanced by
  // every counter step (so it counts on past 2^16; a restarted sender steps back). A held
  // sample has the number of the sample it stands in for.
  std::int64_t sample = 0;
  std::uint16_t a_u_word = 0;  // the SeatInput a_u word the seat was stepped with
  bool held = false;           // filled in by the gap policy, not received
  bool resync = false;         // the first sample after a counted resync
};

template <typename Seat>
class EcuNode {
 public:
  // Checks the cycles (>= 1: Status::out_of_range) and forgets any stream and counters. The
  // seat is configured by its owner (seat()).
  Status configure(const EcuNodeParams& params) noexcept {
    if (params.stats_every == 0 || params.output_every == 0) return Status::out_of_range;
    params_ = params;
    checker_ = ReceiveChecker(params.checker);
    samples_ = 0;
    input_frames_ = 0;
    last_word_ = 0;
    first_sample_ = last_sample_ = 0;
    last_counter_ = 0;
    output_phase_ = stats_phase_ = 0;
    for (std::uint8_t& alive : alive_) alive = 0;
    return Status::ok;
  }

  // Checks one received frame and, for an accepted one, steps the seat for every sample it
  // brings (held samples for a gap first), handing the output frames to `sink`. `now_ns`: any
  // monotonic clock, for the silence timeout. Returns the verdict; nothing refused reaches the
  // seat.
  template <typename Sink>
  FrameVerdict on_frame(const Frame& frame, std::uint64_t now_ns, Sink& sink) noexcept {
    // Members, not locals: the receive interrupt's stack holds only the seat's step (the
    // Cortex-M0+ budget is 256 bytes).
    checker_.check(frame, now_ns, result_);
    if (frame.id == kSeatInput.id && !(frame.flags & kExtendedId)) ++input_frames_;
    const bool accepted = result_.verdict == FrameVerdict::accepted;
    if (!accepted && !result_.hold) return result_.verdict;
    const std::uint16_t counter = result_.payload.sample_counter;
    // The counter step as the checker took it (forward, or back for a restarted sender).
    const std::int64_t sample =
        samples_ == 0
            ? counter
            : last_sample_ +
                  static_cast<std::int16_t>(static_cast<std::uint16_t>(counter - last_counter_));
    last_counter_ = counter;
    if (samples_ > 0) {
      for (unsigned i = 0; i < result_.lost_samples; ++i)
        emit(last_word_, true, false, sample - result_.lost_samples + i, sink);
    }
    if (accepted) {
      emit(result_.payload.words[0], false, result_.resync, sample, sink);
    } else if (samples_ > 0) {
      emit(last_word_, true, false, sample, sink);
    }
    return result_.verdict;
  }

  // Call when the bus has been quiet (a receive timed out): counts bus silence.
  void on_idle(std::uint64_t now_ns) noexcept { checker_.check_silence(now_ns); }
  // Restarts the silence clock (call once when the node starts listening).
  void start(std::uint64_t now_ns) noexcept { checker_.restart(now_ns); }

  Seat& seat() noexcept { return seat_; }
  const Seat& seat() const noexcept { return seat_; }
  const EcuNodeParams& params() const noexcept { return params_; }
  const FaultCounters& counters() const noexcept { return checker_.counters(); }
  // Frames with the SeatInput identifier checked so far (whatever their verdict).
  std::uint64_t input_frames() const noexcept { return input_frames_; }
  std::uint64_t samples() const noexcept { return samples_; }
  // The sender's sample numbers (NodeSample::sample) of the first and the last sample; valid
  // when samples() > 0.
  std::int64_t first_sample() const noexcept { return first_sample_; }
  std::int64_t last_sample() const noexcept { return last_sample_; }

 private:
  template <typename Sink>
  void emit(std::uint16_t word, bool held, bool resync, std::int64_t sample, Sink& sink) noexcept {
    sample_.index = samples_;
    sample_.sample = sample;
    sample_.a_u_word = word;
    sample_.held = held;
    sample_.resync = resync;
    if (samples_ == 0) first_sample_ = sample;
    last_sample_ = sample;
    words_ = samples_ == 0 ? seat_.start(word) : seat_.step(word);
    ++samples_;
    last_word_ = word;
    publish(sink);
    sink.sampled(sample_);
  }

  template <typename Sink>
  void publish(Sink& sink) noexcept {
    const auto counter = static_cast<std::uint16_t>(sample_.index & 0xFFFFu);
    const auto state = static_cast<std::uint8_t>(
        (words_.stuck ? kStuck : 0) | (sample_.held ? kHeld : 0) | (sample_.resync ? kResync : 0));
    const OutputSet set = params_.outputs;
    // index % cycle == 0 as a phase that wraps (no 64-bit division on a 32-bit core).
    const bool output_due = output_phase_ == 0;
    if (++output_phase_ == params_.output_every) output_phase_ = 0;
    const bool stats_due = stats_phase_ == 0;
    if (++stats_phase_ == params_.stats_every) stats_phase_ = 0;
    if (output_due) {
      send(kSeatMotion, counter, 0, state, words_.a_x, words_.x_r, sink);
      if (set != OutputSet::reduced)
        send(kSeatForce, counter, 1, state, words_.v_r, words_.f_f, sink);
    }
    if (set == OutputSet::motion || !stats_due) return;
    // The seat's statistics as of its last completed window; not available before.
    const StatsWords stats = seat_.statistics();
    send(kSeatStats, counter, 2, 0, stats.transmissibility, stats.stick_probability, sink);
    if (set == OutputSet::reduced) return;
    const std::uint64_t faults = checker_.counters().faults();
    const Quantised fault_word{
        static_cast<std::uint16_t>(faults < kUnsignedMax ? faults : kUnsignedMax), false};
    send(kSeatScene, counter, 3, 0, stats.den_hartog_k, fault_word, sink);
  }

  // The frame is a member: off the stack of a receive interrupt (80 bytes with CAN FD room).
  template <typename Sink>
  void send(const MessageSpec& message, std::uint16_t counter, int slot, std::uint8_t flags,
            Quantised first, Quantised second, Sink& sink) noexcept {
    Payload payload;
    payload.sample_counter = counter;
    payload.alive_counter = alive_[slot];
    alive_[slot] = static_cast<std::uint8_t>((alive_[slot] + 1u) & 0x0Fu);
    payload.flags =
        static_cast<std::uint8_t>(flags | ((first.saturated || second.saturated) ? kSaturated : 0));
    payload.words[0] = first.word;
    payload.words[1] = second.word;
    outgoing_.id = message.id;
    outgoing_.length = kPayloadLength;
    outgoing_.flags = 0;
    encode_payload(message, payload, outgoing_.data);
    sink.send(outgoing_);
  }

  Seat seat_;
  EcuNodeParams params_;
  ReceiveChecker checker_;
  Frame outgoing_;
  CheckResult result_;  // of the frame being handled
  NodeSample sample_;   // the sample being published
  SeatWords words_;     // its outputs
  std::uint64_t samples_ = 0;
  std::uint64_t input_frames_ = 0;
  std::int64_t first_sample_ = 0;
  std::int64_t last_sample_ = 0;
  std::uint16_t last_word_ = 0;     // a_u of the last sample (what a held sample repeats)
  std::uint16_t last_counter_ = 0;  // of the last frame that brought a sample (or a hold)
  unsigned output_phase_ = 0, stats_phase_ = 0;  // samples since the last output/stats cycle
  std::uint8_t alive_[4] = {0, 0, 0, 0};         // SeatMotion, SeatForce, SeatStats, SeatScene
};

}  // namespace stickslip::can
