// The ECU's receive side for SeatSensors (codec.hpp): checks each frame (length, E2E CRC, alive
// counter against its sample counter) and keeps the newest good one until the SeatInput sample
// with the same sample counter takes it. Allocation-free, noexcept, no clock.
//
// Why a frame is matched by its sample counter and not simply "the newest": the sensors must
// correct the model at the sample they were measured at; a frame that arrives after its SeatInput
// (or one overtaken by a newer frame before its sample came) would correct the wrong sample, so
// it is counted as unused and the sample runs without it (not measured), as the estimator is
// built to do. The sender therefore sends SeatSensors of sample n before SeatInput of sample n.
// No gap policy: a lost sensor frame is a sample without measurements, never a held one (a held
// travel would tell the filter the seat did not move).
#pragma once

#include <cstdint>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/frame.hpp"

namespace stickslip::can {

enum class SensorVerdict : std::uint8_t {
  accepted,        // kept for the SeatInput sample with its counter
  wrong_length,    // not 8 bytes
  bad_crc,         // E2E CRC wrong (data ID 0x5A11)
  duplicate,       // the same sample counter as the last accepted frame
  alive_mismatch,  // the alive counter did not advance with the sample counter
  not_sensors,     // error, remote, CAN FD or extended frame, or another identifier
};

struct SensorCounters {
  std::uint64_t frames = 0;       // SeatSensors frames checked
  std::uint64_t accepted = 0;     // passed the checks
  std::uint64_t refused = 0;      // wrong_length + bad_crc + duplicate + alive_mismatch
  std::uint64_t used = 0;         // taken by the SeatInput sample of the same counter
  std::uint64_t unused = 0;       // accepted but overtaken before (or arrived after) their sample
  std::uint64_t saturated = 0;    // accepted frames whose sender clipped a signal
  std::uint64_t with_a_x = 0;     // used samples that carried a_x (not "not available")
  std::uint64_t with_travel = 0;  // used samples that carried x_r
};

class SensorReceiver {
 public:
  SensorVerdict take(const Frame& frame) noexcept {
    if ((frame.flags & (kErrorFrame | kRemote | kFd | kExtendedId)) != 0 ||
        frame.id != kSeatSensors.id) {
      return SensorVerdict::not_sensors;
    }
    ++counters_.frames;
    SensorVerdict verdict = SensorVerdict::accepted;
    Payload payload;
    if (frame.length != kPayloadLength) {
      verdict = SensorVerdict::wrong_length;
    } else if (!crc_ok(kSeatSensors, frame.data)) {
      verdict = SensorVerdict::bad_crc;
    } else {
      payload = decode_payload(frame.data);
      if (have_last_) {
        const auto d = static_cast<std::uint16_t>(payload.sample_counter - last_.sample_counter);
        if (d == 0) {
          verdict = SensorVerdict::duplicate;
        } else if (((last_.alive_counter + d) & 0x0Fu) != payload.alive_counter) {
          verdict = SensorVerdict::alive_mismatch;
        }
      }
    }
    if (verdict != SensorVerdict::accepted) {
      ++counters_.refused;
      return verdict;
    }
    if (pending_) ++counters_.unused;  // overtaken before its sample came
    last_ = payload;
    have_last_ = true;
    pending_ = true;
    ++counters_.accepted;
    if ((payload.flags & (kAxSaturated | kXrSaturated)) != 0) ++counters_.saturated;
    return verdict;
  }

  // The sensors of the SeatInput sample with this counter: true and the decoded values (NaN for
  // a sensor reported not available) when the kept frame is that sample's; false (both NaN, the
  // estimator's "not measured") when there is none. A kept frame of another sample is dropped
  // as unused, since samples only move forward.
  template <typename T>
  bool sample(std::uint16_t sample_counter, T& a_x_m_per_s2, T& x_r_m) noexcept {
    a_x_m_per_s2 = physical<T>(kSeatSensors.signals[0], kSignedNotAvailableWord);
    x_r_m = a_x_m_per_s2;
    if (!pending_) return false;
    pending_ = false;
    if (last_.sample_counter != sample_counter) {
      ++counters_.unused;
      return false;
    }
    ++counters_.used;
    a_x_m_per_s2 = physical<T>(kSeatSensors.signals[0], last_.words[0]);
    x_r_m = physical<T>(kSeatSensors.signals[1], last_.words[1]);
    if (a_x_m_per_s2 == a_x_m_per_s2) ++counters_.with_a_x;
    if (x_r_m == x_r_m) ++counters_.with_travel;
    return true;
  }

  const SensorCounters& counters() const noexcept { return counters_; }

 private:
  static constexpr std::uint16_t kSignedNotAvailableWord = 0x8000u;

  SensorCounters counters_;
  Payload last_;
  bool have_last_ = false;
  bool pending_ = false;  // last_ not yet taken by a sample
};

}  // namespace stickslip::can
