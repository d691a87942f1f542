// The stickslip CAN messages (docs/CAN.md, docs/can/stickslip.dbc) and pure encode/decode
// functions on 8-byte payloads. Allocation-free, noexcept, standard headers only.
//
// Every message has the same 8-byte layout (Intel byte order):
//   byte 0     CRC-8 SAE J1850 over the 16-bit data ID and bytes 1..7 (crc8.hpp, e2e_crc)
//   byte 1     bits 0..3 alive counter (+1 mod 16 per frame of that message), bits 4..7 flags
//   bytes 2-3  sample counter: the sample index mod 2^16
//   bytes 4-5  signal 0, 16 bits
//   bytes 6-7  signal 1, 16 bits
// Signals are signed or unsigned 16-bit integers with a power-of-two scale (2^-fraction_bits
// units per bit), so decoding is exact in float and double and a quantised sample survives any
// number of encode/decode round trips unchanged.
//
// Scaling and overflow: quantise() rounds to nearest (halves away from zero) and saturates to
// [-32767, 32767] (signed) or [0, 65534] (unsigned), reporting the saturation; -32768 (0x8000)
// and 65535 (0xFFFF) are reserved as "not available" (NaN encodes as not available).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "stickslip/can/crc8.hpp"
#include "stickslip/can/frame.hpp"

namespace stickslip::can {

inline constexpr std::uint8_t kPayloadLength =
    8;  // every stickslip message is a full classic frame
inline constexpr std::int16_t kSignedNotAvailable = -32768;
inline constexpr std::uint16_t kUnsignedNotAvailable = 0xFFFFu;
inline constexpr std::int16_t kSignedMax = 32767;
inline constexpr std::uint16_t kUnsignedMax = 0xFFFEu;

struct SignalSpec {
  const char* name;
  bool is_signed;
  int fraction_bits;  // physical value = raw * 2^-fraction_bits
  const char* unit;
};

// Four flag bits (byte 1, bits 4..7); name nullptr where a bit is unused (always sent as 0).
struct MessageSpec {
  const char* name;
  std::uint32_t id;       // 11-bit identifier
  std::uint16_t data_id;  // E2E data ID folded into the CRC, never transmitted
  SignalSpec signals[2];  // bytes 4-5 and 6-7
  const char* flags[4];
};

// Cab-floor acceleration in (host or sensor -> ECU), one sample per frame at 1 kHz.
inline constexpr MessageSpec kSeatInput{"SeatInput",
                                        0x100,
                                        0x5A10,
                                        {{"a_u", true, 10, "m/s^2"}, {"a_seat", true, 10, "m/s^2"}},
                                        {"a_u_saturated", "a_seat_saturated", nullptr, nullptr}};
// The seat's own sensors (host or sensor -> ECU) for the state estimator, sample for sample with
// SeatInput (the same sample counter; sent before the SeatInput frame of its sample): the
// measured seat acceleration a_x (the SeatInput scale) and the measured suspension travel x_r
// (2^-16 m = 15 um, finer than a 0.1 mm travel sensor). Either may be not available.
inline constexpr MessageSpec kSeatSensors{"SeatSensors",
                                          0x101,
                                          0x5A11,
                                          {{"a_x", true, 10, "m/s^2"}, {"x_r", true, 16, "m"}},
                                          {"a_x_saturated", "x_r_saturated", nullptr, nullptr}};
// ECU outputs, every sample.
inline constexpr MessageSpec kSeatMotion{"SeatMotion",
                                         0x180,
                                         0x5A80,
                                         {{"a_x", true, 10, "m/s^2"}, {"x_r", true, 16, "m"}},
                                         {"stuck", "held", "resync", "saturated"}};
inline constexpr MessageSpec kSeatForce{"SeatForce",
                                        0x181,
                                        0x5A81,
                                        {{"v_r", true, 12, "m/s"}, {"f_f", true, 6, "N"}},
                                        {"stuck", "held", "resync", "saturated"}};
// ECU running statistics, every Nth sample (10 by default: 100 Hz).
inline constexpr MessageSpec kSeatStats{"SeatStats",
                                        0x182,
                                        0x5A82,
                                        {{"T_ax", false, 12, ""}, {"p_stick", false, 15, ""}},
                                        {nullptr, nullptr, nullptr, "saturated"}};
inline constexpr MessageSpec kSeatScene{"SeatScene",
                                        0x183,
                                        0x5A83,
                                        {{"K", false, 10, ""}, {"faults", false, 0, "frames"}},
                                        {nullptr, nullptr, nullptr, "saturated"}};

// The state estimator's outputs (observer/state_estimator.hpp; the node's --estimator): the
// corrected seat state every output cycle, the friction levels it has learnt every stats cycle.
inline constexpr MessageSpec kSeatEstimate{
    "SeatEstimate",
    0x184,
    0x5A84,
    {{"x_r_est", true, 16, "m"}, {"v_r_est", true, 12, "m/s"}},
    {"stuck", "held", "resync", "saturated"}};
inline constexpr MessageSpec kSeatEstimateForce{
    "SeatEstimateForce",
    0x185,
    0x5A85,
    {{"f_f_est", true, 6, "N"}, {"a_bias_est", true, 14, "m/s^2"}},
    {"stuck", "held", "resync", "saturated"}};
// F_fk and F_fs estimates: not available until converged (the start value's weight below 5 %).
inline constexpr MessageSpec kFrictionEstimate{
    "FrictionEstimate",
    0x186,
    0x5A86,
    {{"F_fk_est", false, 6, "N"}, {"F_fs_est", false, 6, "N"}},
    {nullptr, nullptr, nullptr, "saturated"}};

// The controller's answer to one sample (`stickslip controller` -> `stickslip plant`, or the
// user's ECU): f_a, the actuator force to hold over the step after the sample whose counter it
// carries (1/16 N per bit, +-2047.9 N), and u, the controller's command before the actuator's
// limit and lag (for the record). "passive" (or f_a not available, 0x8000) asks for no force.
inline constexpr MessageSpec kActuatorCommand{"ActuatorCommand",
                                              0x190,
                                              0x5A90,
                                              {{"f_a", true, 4, "N"}, {"u", true, 4, "N"}},
                                              {"passive", nullptr, nullptr, "saturated"}};
enum CommandFlag : std::uint8_t { kCommandPassive = 1u << 0, kCommandSaturated = 1u << 3 };

inline constexpr const MessageSpec* kMessages[] = {
    &kSeatInput, &kSeatSensors,  &kSeatMotion,        &kSeatForce,        &kSeatStats,
    &kSeatScene, &kSeatEstimate, &kSeatEstimateForce, &kFrictionEstimate, &kActuatorCommand};
inline constexpr const MessageSpec* kInputMessages[] = {&kSeatInput, &kSeatSensors};
inline constexpr const MessageSpec* kOutputMessages[] = {
    &kSeatMotion,   &kSeatForce,         &kSeatStats,       &kSeatScene,
    &kSeatEstimate, &kSeatEstimateForce, &kFrictionEstimate};

// Flag bits (as Payload::flags, bits 0..3).
enum InputFlag : std::uint8_t { kAuSaturated = 1u << 0, kASeatSaturated = 1u << 1 };
enum SensorFlag : std::uint8_t { kAxSaturated = 1u << 0, kXrSaturated = 1u << 1 };
enum OutputFlag : std::uint8_t {
  kStuck = 1u << 0,      // SeatMotion/SeatForce: stuck at the end of the step
  kHeld = 1u << 1,       // the sample was held (gap policy), not received
  kResync = 1u << 2,     // first sample after a counted resync
  kSaturated = 1u << 3,  // a signal of this frame was clipped by quantise()
};

// The decoded 8 bytes: header fields and the two raw 16-bit signal words.
struct Payload {
  std::uint16_t sample_counter = 0;
  std::uint8_t alive_counter = 0;   // 0..15
  std::uint8_t flags = 0;           // 0..15
  std::uint16_t words[2] = {0, 0};  // raw signals (two's complement where signed)
};

struct Quantised {
  std::uint16_t word;  // the raw value as transmitted
  bool saturated;      // the value was outside the range and was clipped
};

inline std::uint16_t signed_word(std::int16_t raw) noexcept {
  return static_cast<std::uint16_t>(raw);
}
inline std::int16_t word_as_signed(std::uint16_t word) noexcept {
  // Two's complement without implementation-defined conversion.
  return word < 0x8000u ? static_cast<std::int16_t>(word)
                        : static_cast<std::int16_t>(static_cast<int>(word) - 65536);
}

// 2^n and 2^-n, exactly, for 0 <= n <= 31 (a signal's fraction_bits), from the exponent field:
// a product by either is ldexp(x, +-n) bit for bit wherever no bit falls below the subnormal
// range, without the library call, a division or an integer conversion (each a software
// routine on a core without an FPU).
template <typename T>
T exact_power_of_two(int e) noexcept {
  static_assert(std::numeric_limits<T>::is_iec559 && (sizeof(T) == 4 || sizeof(T) == 8),
                "IEEE float or double");
  T value;
  if constexpr (sizeof(T) == 4) {
    const std::uint32_t bits = static_cast<std::uint32_t>(127 + e) << 23;
    std::memcpy(&value, &bits, sizeof value);
  } else {
    const std::uint64_t bits = static_cast<std::uint64_t>(1023 + e) << 52;
    std::memcpy(&value, &bits, sizeof value);
  }
  return value;
}
template <typename T>
T power_of_two(int n) noexcept {
  return exact_power_of_two<T>(n);
}
template <typename T>
T inverse_power_of_two(int n) noexcept {
  return exact_power_of_two<T>(-n);
}

// Physical value -> raw word; see "Scaling and overflow" above. T is float or double.
template <typename T>
Quantised quantise(const SignalSpec& signal, T value) noexcept {
  if (value != value) {
    return {signal.is_signed ? signed_word(kSignedNotAvailable) : kUnsignedNotAvailable, false};
  }
  // Anything that would round beyond the largest code saturates. Every code's value is below
  // 2^16 (n >= 0), so a larger magnitude (infinity, 1e300) saturates before it is scaled and
  // nothing overflows; below it the product by 2^n (n <= 31) is exact, ldexp's value, and is
  // checked against the codes: one product, where a software product or division costs about a
  // hundred instructions on a core without an FPU.
  static_assert(kSignedMax == 32767 && kUnsignedMax == 65534, "the halves above the codes");
  const T beyond_every_code = T(65536);
  const T product = value >= beyond_every_code    ? beyond_every_code
                    : value <= -beyond_every_code ? -beyond_every_code
                                                  : value * power_of_two<T>(signal.fraction_bits);
  if (product >= (signal.is_signed ? T(32767.5) : T(65534.5))) {
    return {signal.is_signed ? signed_word(kSignedMax) : kUnsignedMax, true};
  }
  if (product <= (signal.is_signed ? T(-32767.5) : T(-0.5))) {
    return {signal.is_signed ? signed_word(-kSignedMax) : std::uint16_t{0}, true};
  }
  const T scaled = std::round(product);  // |product| < 65534.5: the code
  if (signal.is_signed) return {signed_word(static_cast<std::int16_t>(scaled)), false};
  return {static_cast<std::uint16_t>(scaled), false};
}

inline bool not_available(const SignalSpec& signal, std::uint16_t word) noexcept {
  return signal.is_signed ? word == signed_word(kSignedNotAvailable)
                          : word == kUnsignedNotAvailable;
}

// Raw word -> physical value, exact; NaN for the not-available code.
template <typename T>
T physical(const SignalSpec& signal, std::uint16_t word) noexcept {
  if (not_available(signal, word)) return T(NAN);
  const T raw = signal.is_signed ? T(word_as_signed(word)) : T(word);
  return raw * inverse_power_of_two<T>(signal.fraction_bits);  // exact
}

// Writes the 8 bytes of `message` (CRC included).
inline void encode_payload(const MessageSpec& message, const Payload& payload,
                           std::uint8_t out[kPayloadLength]) noexcept {
  out[1] =
      static_cast<std::uint8_t>((payload.alive_counter & 0x0Fu) | ((payload.flags & 0x0Fu) << 4));
  out[2] = static_cast<std::uint8_t>(payload.sample_counter & 0xFFu);
  out[3] = static_cast<std::uint8_t>(payload.sample_counter >> 8);
  out[4] = static_cast<std::uint8_t>(payload.words[0] & 0xFFu);
  out[5] = static_cast<std::uint8_t>(payload.words[0] >> 8);
  out[6] = static_cast<std::uint8_t>(payload.words[1] & 0xFFu);
  out[7] = static_cast<std::uint8_t>(payload.words[1] >> 8);
  out[0] = e2e_crc(message.data_id, out);
}

// Reads the fields of 8 bytes (no check; see crc_ok()).
inline Payload decode_payload(const std::uint8_t in[kPayloadLength]) noexcept {
  Payload payload;
  payload.alive_counter = static_cast<std::uint8_t>(in[1] & 0x0Fu);
  payload.flags = static_cast<std::uint8_t>(in[1] >> 4);
  payload.sample_counter = static_cast<std::uint16_t>(in[2] | (in[3] << 8));
  payload.words[0] = static_cast<std::uint16_t>(in[4] | (in[5] << 8));
  payload.words[1] = static_cast<std::uint16_t>(in[6] | (in[7] << 8));
  return payload;
}

inline bool crc_ok(const MessageSpec& message, const std::uint8_t in[kPayloadLength]) noexcept {
  return in[0] == e2e_crc(message.data_id, in);
}

// A whole classic frame of `message`.
inline Frame make_frame(const MessageSpec& message, const Payload& payload) noexcept {
  Frame frame;
  frame.id = message.id;
  frame.length = kPayloadLength;
  encode_payload(message, payload, frame.data);
  return frame;
}

// The SeatInput frame for sample `sample_index` (the alive counter follows the sample counter,
// as a sender that sends every sample does). `saturated` reports a clipped a_u.
template <typename T>
Frame make_input_frame(T a_u_m_per_s2, std::uint64_t sample_index, bool* saturated = nullptr,
                       T a_seat_m_per_s2 = T(NAN)) noexcept {
  const Quantised a_u = quantise(kSeatInput.signals[0], a_u_m_per_s2);
  const Quantised a_seat = quantise(kSeatInput.signals[1], a_seat_m_per_s2);
  Payload payload;
  payload.sample_counter = static_cast<std::uint16_t>(sample_index & 0xFFFFu);
  payload.alive_counter = static_cast<std::uint8_t>(sample_index & 0x0Fu);
  payload.flags = static_cast<std::uint8_t>((a_u.saturated ? kAuSaturated : 0) |
                                            (a_seat.saturated ? kASeatSaturated : 0));
  payload.words[0] = a_u.word;
  payload.words[1] = a_seat.word;
  if (saturated != nullptr) *saturated = a_u.saturated;
  return make_frame(kSeatInput, payload);
}

// The SeatSensors frame for sample `sample_index` (counters as make_input_frame()); NaN for a
// sensor that is not fitted. `saturated` reports a clipped signal.
template <typename T>
Frame make_sensor_frame(T a_x_m_per_s2, T x_r_m, std::uint64_t sample_index,
                        bool* saturated = nullptr) noexcept {
  const Quantised a_x = quantise(kSeatSensors.signals[0], a_x_m_per_s2);
  const Quantised x_r = quantise(kSeatSensors.signals[1], x_r_m);
  Payload payload;
  payload.sample_counter = static_cast<std::uint16_t>(sample_index & 0xFFFFu);
  payload.alive_counter = static_cast<std::uint8_t>(sample_index & 0x0Fu);
  payload.flags = static_cast<std::uint8_t>((a_x.saturated ? kAxSaturated : 0) |
                                            (x_r.saturated ? kXrSaturated : 0));
  payload.words[0] = a_x.word;
  payload.words[1] = x_r.word;
  if (saturated != nullptr) *saturated = a_x.saturated || x_r.saturated;
  return make_frame(kSeatSensors, payload);
}

// A sensor value exactly as the ECU sees it after the bus (signal 0: a_x, 1: x_r).
template <typename T>
T quantised_sensor(int signal, T value) noexcept {
  const SignalSpec& spec = kSeatSensors.signals[signal];
  return physical<T>(spec, quantise(spec, value).word);
}

// a_u exactly as the ECU sees it after the bus: quantise then decode (the quantisation contract
// of replay: `simulate` on these samples equals the replayed run bit for bit).
template <typename T>
T quantised_input(T a_u_m_per_s2) noexcept {
  return physical<T>(kSeatInput.signals[0], quantise(kSeatInput.signals[0], a_u_m_per_s2).word);
}

// The ActuatorCommand frame answering sample `sample_index`: the force to hold (NaN or
// passive: no force) and the controller's command (NaN: not available).
template <typename T>
Frame make_command_frame(T force_n, T command_n, std::uint64_t sample_index,
                         bool passive = false) noexcept {
  const Quantised f = quantise(kActuatorCommand.signals[0], passive ? T(NAN) : force_n);
  const Quantised u = quantise(kActuatorCommand.signals[1], command_n);
  Payload payload;
  payload.sample_counter = static_cast<std::uint16_t>(sample_index & 0xFFFFu);
  payload.alive_counter = static_cast<std::uint8_t>(sample_index & 0x0Fu);
  payload.flags = static_cast<std::uint8_t>((passive ? kCommandPassive : 0) |
                                            (f.saturated || u.saturated ? kCommandSaturated : 0));
  payload.words[0] = f.word;
  payload.words[1] = u.word;
  return make_frame(kActuatorCommand, payload);
}

// The message with this identifier, or nullptr.
inline const MessageSpec* find_message(std::uint32_t id) noexcept {
  for (const MessageSpec* message : kMessages)
    if (message->id == id) return message;
  return nullptr;
}

}  // namespace stickslip::can
