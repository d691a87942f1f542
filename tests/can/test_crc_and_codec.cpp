// CRC-8 SAE J1850 and the frame codec (lib/can): check value, E2E data ID, exact round trips,
// rounding and saturation.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/can/crc8.hpp"

using namespace stickslip::can;

TEST_GROUP(Crc8){};

TEST(Crc8, CheckValueOf123456789Is0x4B) {
  const char* text = "123456789";
  const std::uint8_t crc = crc8_sae_j1850(reinterpret_cast<const std::uint8_t*>(text), 9);
  LONGS_EQUAL(0x4B, crc);
  // And it is usable at compile time on an MCU (constexpr), giving the same value.
  constexpr std::uint8_t bytes[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  static_assert(crc8_sae_j1850(bytes, 9) == 0x4B, "CRC-8 SAE J1850 check value");
}

TEST(Crc8, EverySingleBitFlipOfThePayloadIsDetected) {
  const Frame frame = make_input_frame(1.25, 1234);
  CHECK_TRUE(crc_ok(kSeatInput, frame.data));
  for (int byte = 0; byte < 8; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      std::uint8_t corrupted[8];
      std::memcpy(corrupted, frame.data, 8);
      corrupted[byte] = static_cast<std::uint8_t>(corrupted[byte] ^ (1u << bit));
      CHECK_FALSE(crc_ok(kSeatInput, corrupted));
    }
  }
}

TEST(Crc8, E2eCrcIsTheCrcOfTheDataIdThenPayloadBytesOneToSeven) {
  // e2e_crc() is unrolled for the MCUs; its definition is the CRC of its 9 bytes.
  std::uint32_t state = 12345u;
  for (const std::uint16_t data_id : {std::uint16_t{0x0000}, std::uint16_t{0x0100},
                                      std::uint16_t{0x1234}, std::uint16_t{0xFFFF}}) {
    for (int trial = 0; trial < 1000; ++trial) {
      std::uint8_t payload[8];
      for (std::uint8_t& byte : payload) {
        state = state * 1664525u + 1013904223u;
        byte = static_cast<std::uint8_t>(state >> 24);
      }
      const std::uint8_t bytes[9] = {static_cast<std::uint8_t>(data_id & 0xFFu),
                                     static_cast<std::uint8_t>(data_id >> 8),
                                     payload[1],
                                     payload[2],
                                     payload[3],
                                     payload[4],
                                     payload[5],
                                     payload[6],
                                     payload[7]};
      LONGS_EQUAL(crc8_sae_j1850(bytes, 9), e2e_crc(data_id, payload));
    }
  }
}

TEST(Crc8, DataIdIsFoldedIntoTheCrc) {
  // The same bytes under another message's data ID fail: a frame cannot pass as another message.
  const Frame frame = make_input_frame(-0.5, 7);
  for (const MessageSpec* message : kOutputMessages) CHECK_FALSE(crc_ok(*message, frame.data));
}

TEST_GROUP(Codec){};

TEST(Codec, EverySignedCodeRoundTripsExactlyInDoubleAndFloat) {
  const SignalSpec& a_u = kSeatInput.signals[0];
  for (int raw = -kSignedMax; raw <= kSignedMax; ++raw) {
    const auto word = static_cast<std::uint16_t>(static_cast<std::int16_t>(raw));
    const double value = physical<double>(a_u, word);
    const float value_f = physical<float>(a_u, word);
    CHECK_EQUAL(static_cast<double>(raw) / 1024.0, value);
    CHECK_EQUAL(value, static_cast<double>(value_f));
    const Quantised back = quantise(a_u, value);
    LONGS_EQUAL(word, back.word);
    CHECK_FALSE(back.saturated);
    LONGS_EQUAL(word, quantise(a_u, value_f).word);
  }
}

TEST(Codec, QuantiseRoundsToTheNearestCode) {
  const SignalSpec& a_u = kSeatInput.signals[0];
  const double lsb = 1.0 / 1024.0;
  for (double value = -3.0; value < 3.0; value += 0.0123) {
    const double decoded = physical<double>(a_u, quantise(a_u, value).word);
    CHECK(std::fabs(decoded - value) <= 0.5 * lsb);
  }
  // Halves round away from zero.
  CHECK_EQUAL(2.0 * lsb, physical<double>(a_u, quantise(a_u, 1.5 * lsb).word));
  CHECK_EQUAL(-2.0 * lsb, physical<double>(a_u, quantise(a_u, -1.5 * lsb).word));
}

namespace {

// quantise() as it stood with the library's ldexp: the oracle for its products by 2^n.
template <typename T>
Quantised quantise_with_ldexp(const SignalSpec& signal, T value) {
  if (value != value)
    return {signal.is_signed ? signed_word(kSignedNotAvailable) : kUnsignedNotAvailable, false};
  const T max_code = signal.is_signed ? T(kSignedMax) : T(kUnsignedMax);
  const T upper = std::ldexp(max_code + T(0.5), -signal.fraction_bits);
  const T lower = signal.is_signed ? -upper : -std::ldexp(T(0.5), -signal.fraction_bits);
  if (value >= upper) return {signal.is_signed ? signed_word(kSignedMax) : kUnsignedMax, true};
  if (value <= lower) return {signal.is_signed ? signed_word(-kSignedMax) : std::uint16_t{0}, true};
  const T scaled = std::round(std::ldexp(value, signal.fraction_bits));
  if (signal.is_signed) return {signed_word(static_cast<std::int16_t>(scaled)), false};
  return {static_cast<std::uint16_t>(scaled), false};
}

// Values that probe every branch and rounding edge of a signal: each code's value, the halves
// between codes and their neighbours one ulp either side, the range edges, tiny and subnormal
// numbers, infinities and NaN.
template <typename T>
std::vector<T> probe_values(const SignalSpec& signal) {
  std::vector<T> values;
  const T lsb = std::ldexp(T(1), -signal.fraction_bits);
  const int top = signal.is_signed ? kSignedMax : kUnsignedMax;
  const T inf = std::numeric_limits<T>::infinity();
  for (int code = signal.is_signed ? -top - 1 : -1; code <= top + 1;
       code += code % 97 == 0 ? 1 : 13) {
    for (const T at : {T(code), T(code) + T(0.5), T(code) - T(0.5)}) {
      const T v = at * lsb;
      values.push_back(v);
      values.push_back(std::nextafter(v, inf));
      values.push_back(std::nextafter(v, -inf));
    }
  }
  for (const T v : {std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(), T(1e-30),
                    std::numeric_limits<T>::max(), inf, std::numeric_limits<T>::quiet_NaN()}) {
    values.push_back(v);
    values.push_back(-v);
  }
  return values;
}

template <typename T>
long mismatches_against_ldexp() {
  long mismatched = 0, compared = 0;
  for (const MessageSpec* message : kMessages) {
    for (const SignalSpec& signal : message->signals) {
      for (const T value : probe_values<T>(signal)) {
        const Quantised a = quantise(signal, value);
        const Quantised b = quantise_with_ldexp(signal, value);
        ++compared;
        if (a.word != b.word || a.saturated != b.saturated) ++mismatched;
      }
    }
  }
  CHECK(compared > 100000);
  return mismatched;
}

}  // namespace

TEST(Codec, QuantiseGivesLdexpsWordsBitForBitInDoubleAndFloat) {
  LONGS_EQUAL(0, mismatches_against_ldexp<double>());
  LONGS_EQUAL(0, mismatches_against_ldexp<float>());
}

namespace {

// physical() for every word of every signal against ldexp(raw, -fraction_bits); NaN for the
// not-available word.
template <typename T>
long physical_mismatches_against_ldexp() {
  long mismatched = 0;
  for (const MessageSpec* message : kMessages) {
    for (const SignalSpec& signal : message->signals) {
      for (std::uint32_t word = 0; word <= 0xFFFFu; ++word) {
        const auto w = static_cast<std::uint16_t>(word);
        const T got = physical<T>(signal, w);
        if (not_available(signal, w)) {
          if (got == got) ++mismatched;
          continue;
        }
        const T raw = signal.is_signed ? T(word_as_signed(w)) : T(w);
        if (got != std::ldexp(raw, -signal.fraction_bits)) ++mismatched;
      }
    }
  }
  return mismatched;
}

}  // namespace

TEST(Codec, PhysicalGivesLdexpsValuesBitForBitInDoubleAndFloat) {
  LONGS_EQUAL(0, physical_mismatches_against_ldexp<double>());
  LONGS_EQUAL(0, physical_mismatches_against_ldexp<float>());
  // The exponent field is the power: 2^-31 .. 2^0.
  for (int n = 0; n <= 31; ++n) {
    CHECK(inverse_power_of_two<float>(n) == std::ldexp(1.0f, -n));
    CHECK(inverse_power_of_two<double>(n) == std::ldexp(1.0, -n));
  }
}

TEST(Codec, OutOfRangeValuesSaturateAndSaySo) {
  const SignalSpec& a_u = kSeatInput.signals[0];
  Quantised q = quantise(a_u, 40.0);
  CHECK_TRUE(q.saturated);
  LONGS_EQUAL(kSignedMax, word_as_signed(q.word));
  q = quantise(a_u, -1e300);
  CHECK_TRUE(q.saturated);
  LONGS_EQUAL(-kSignedMax, word_as_signed(q.word));
  q = quantise(a_u, std::numeric_limits<double>::infinity());
  CHECK_TRUE(q.saturated);
  // The largest value that still rounds to the largest code is not saturated.
  q = quantise(a_u, (kSignedMax + 0.49) / 1024.0);
  CHECK_FALSE(q.saturated);
  LONGS_EQUAL(kSignedMax, word_as_signed(q.word));
  // Unsigned signals: negative values clip to 0, large ones to 65534; 65535 stays reserved.
  const SignalSpec& t_ax = kSeatStats.signals[0];
  q = quantise(t_ax, -0.1);
  CHECK_TRUE(q.saturated);
  LONGS_EQUAL(0, q.word);
  q = quantise(t_ax, 1e6);
  CHECK_TRUE(q.saturated);
  LONGS_EQUAL(kUnsignedMax, q.word);
  // NaN is "not available", decoded as NaN, never as a number.
  q = quantise(a_u, std::numeric_limits<double>::quiet_NaN());
  CHECK_TRUE(not_available(a_u, q.word));
  const double decoded = physical<double>(a_u, q.word);
  CHECK_TRUE(decoded != decoded);
}

TEST(Codec, InputFrameCarriesCountersFlagsAndSaturation) {
  bool saturated = true;
  Frame frame = make_input_frame(0.75, 0x12345, &saturated);
  CHECK_FALSE(saturated);
  LONGS_EQUAL(kSeatInput.id, frame.id);
  LONGS_EQUAL(8, frame.length);
  Payload payload = decode_payload(frame.data);
  LONGS_EQUAL(0x2345, payload.sample_counter);
  LONGS_EQUAL(0x5, payload.alive_counter);
  LONGS_EQUAL(0, payload.flags);
  CHECK_EQUAL(0.75, physical<double>(kSeatInput.signals[0], payload.words[0]));
  CHECK_TRUE(not_available(kSeatInput.signals[1], payload.words[1]));

  frame = make_input_frame(-50.0, 3, &saturated);
  CHECK_TRUE(saturated);
  payload = decode_payload(frame.data);
  LONGS_EQUAL(kAuSaturated, payload.flags & kAuSaturated);
  CHECK_EQUAL(-kSignedMax / 1024.0, physical<double>(kSeatInput.signals[0], payload.words[0]));
  CHECK_TRUE(crc_ok(kSeatInput, frame.data));
}

TEST(Codec, PayloadFieldsRoundTripForEveryMessage) {
  for (const MessageSpec* message : kMessages) {
    Payload in;
    in.sample_counter = 0xBEEF;
    in.alive_counter = 9;
    in.flags = 0xA;
    in.words[0] = 0x8001;
    in.words[1] = 0x7FFE;
    std::uint8_t bytes[8];
    encode_payload(*message, in, bytes);
    CHECK_TRUE(crc_ok(*message, bytes));
    const Payload out = decode_payload(bytes);
    LONGS_EQUAL(in.sample_counter, out.sample_counter);
    LONGS_EQUAL(in.alive_counter, out.alive_counter);
    LONGS_EQUAL(in.flags, out.flags);
    LONGS_EQUAL(in.words[0], out.words[0]);
    LONGS_EQUAL(in.words[1], out.words[1]);
    POINTERS_EQUAL(message, find_message(message->id));
  }
  POINTERS_EQUAL(nullptr, find_message(0x7FF));
}

TEST(Codec, QuantisedInputIsIdempotent) {
  for (double value = -30.0; value < 30.0; value += 0.377) {
    const double once = quantised_input(value);
    CHECK_EQUAL(once, quantised_input(once));
  }
}
