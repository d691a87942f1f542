// The DBC reader (sim_host/src/io/dbc.cpp): the project's own docs/can/stickslip.dbc decodes every
// field exactly as lib's codec does; the Motorola start-bit convention, extended ids, value
// tables, comments and exact decimal scaling; refusals naming file and line.
#include <cmath>
#include <cstdint>
#include <string>

#include "stickslip/can/codec.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/dbc.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::ByteOrder;
using stickslip::host::Dbc;
using stickslip::host::DbcMessage;
using stickslip::host::DbcSignal;
using stickslip::host::decode_signal;
using stickslip::host::HostError;
using stickslip::host::parse_dbc;
using stickslip::host::raw_value;
using stickslip::host::read_dbc;
using stickslip::test::bit_equal;
namespace can = stickslip::can;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_dbc(text, "car.dbc");
  } catch (const HostError& error) {
    return error.what();
  }
  return "(no error)";
}

const DbcSignal& signal_of(const Dbc& dbc, const char* message, const char* signal) {
  const DbcMessage* found = dbc.find_message(message);
  CHECK(found != nullptr);
  const DbcSignal* result = found->find_signal(signal);
  CHECK(result != nullptr);
  return *result;
}

double decoded(const DbcSignal& signal, const std::uint8_t* data, std::size_t length = 8) {
  const auto value = decode_signal(signal, data, length);
  CHECK(value.has_value());
  return *value;
}

constexpr const char* kVehicle = R"(VERSION ""

NS_ :
	CM_
	VAL_
	BA_DEF_

BS_:

BU_: Cab Logger

BO_ 2365526577 CabFloor: 8 Cab
 SG_ AccZ : 7|16@0- (0.001,0) [-32.768|32.767] "g" Logger,Other
 SG_ Odd : 3|10@0+ (1,0) [0|1023] "" Logger
 SG_ Tilt : 16|12@1- (0.05,-10) [-112.4|92.35] "deg" Logger

BO_ 291 Body: 2 Cab
 SG_ Door : 0|1@1+ (1,0) [0|1] "" Logger

BA_DEF_ BO_ "GenMsgCycleTime" INT 0 65535;
CM_ BO_ 2365526577 "Cab floor accelerometer";
CM_ SG_ 2365526577 AccZ "Vertical
acceleration";
VAL_ 291 Door 0 "closed" 1 "open" ;
)";

}  // namespace

TEST_GROUP(DbcReader){};

TEST(DbcReader, ProjectDbcDecodesEveryFieldAsTheCodec) {
  const Dbc dbc = read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  std::uint32_t state = 12345u;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  for (const can::MessageSpec* spec : can::kMessages) {
    const DbcMessage* message = dbc.find_message(spec->name);
    CHECK(message != nullptr);
    LONGS_EQUAL(spec->id, message->id);
    CHECK_FALSE(message->extended);
    for (int n = 0; n < 2000; ++n) {
      can::Payload payload;
      payload.sample_counter = static_cast<std::uint16_t>(next());
      payload.alive_counter = static_cast<std::uint8_t>(next() & 0x0F);
      payload.flags = static_cast<std::uint8_t>(next() & 0x0F);
      payload.words[0] = static_cast<std::uint16_t>(next());
      payload.words[1] = static_cast<std::uint16_t>(next());
      const can::Frame frame = can::make_frame(*spec, payload);
      const can::Payload back = can::decode_payload(frame.data);
      CHECK(bit_equal(frame.data[0], decoded(*message->find_signal("CRC"), frame.data)));
      CHECK(bit_equal(back.alive_counter,
                      decoded(*message->find_signal("AliveCounter"), frame.data)));
      CHECK(bit_equal(back.sample_counter,
                      decoded(*message->find_signal("SampleCounter"), frame.data)));
      for (int bit = 0; bit < 4; ++bit) {
        if (spec->flags[bit] == nullptr) continue;
        CHECK(bit_equal((back.flags >> bit) & 1u,
                        decoded(*message->find_signal(spec->flags[bit]), frame.data)));
      }
      for (int s = 0; s < 2; ++s) {
        const can::SignalSpec& field = spec->signals[s];
        const DbcSignal* signal = message->find_signal(field.name);
        CHECK(signal != nullptr);
        STRCMP_EQUAL(field.unit, signal->unit.c_str());
        if (can::not_available(field, back.words[s])) continue;  // the codec's NaN
        CHECK(bit_equal(can::physical<double>(field, back.words[s]), decoded(*signal, frame.data)));
      }
    }
  }
}

TEST(DbcReader, MotorolaStartBitIsTheMostSignificantBitInDbcNumbering) {
  const Dbc dbc = parse_dbc(kVehicle, "vehicle.dbc");
  // 3|10@0+: byte 0 bits 3..0 then byte 1 bits 7..2, most significant first.
  const std::uint8_t data[8] = {0x0A, 0xBC, 0, 0, 0, 0, 0, 0};
  LONGS_EQUAL(0x2AF, *raw_value(signal_of(dbc, "CabFloor", "Odd"), data, 8));
  // 7|16@0-: bytes 0-1 big-endian, signed; 0.001 g per bit.
  const std::uint8_t negative[8] = {0xFC, 0x18, 0, 0, 0, 0, 0, 0};
  const DbcSignal& accz = signal_of(dbc, "CabFloor", "AccZ");
  CHECK(accz.byte_order == ByteOrder::kMotorola);
  CHECK(accz.is_signed);
  LONGS_EQUAL(-1000, *raw_value(accz, negative, 8));
  CHECK(bit_equal(-1.0, decoded(accz, negative)));
  LONGS_EQUAL(2, accz.bytes_needed);
}

TEST(DbcReader, ScalingRoundsOnceToTheNearestDoubleOfTheDecimalResult) {
  const Dbc dbc = parse_dbc(kVehicle, "vehicle.dbc");
  // The oracle is the literal: the compiler's correctly rounded double of the exact decimal
  // result, which is also what canmatrix's decimal arithmetic gives.
  const DbcSignal& tilt = signal_of(dbc, "CabFloor", "Tilt");
  const std::uint8_t data[8] = {0, 0, 0x06, 0x00, 0, 0, 0, 0};  // raw 6: 6 * 0.05 - 10
  CHECK(bit_equal(-9.7, decoded(tilt, data)));
  const std::uint8_t negative[8] = {0, 0, 0xFF, 0x0F, 0, 0, 0, 0};  // raw -1 (12 bits)
  CHECK(bit_equal(-10.05, decoded(tilt, negative)));
  const Dbc tenths =
      parse_dbc("BO_ 1 M: 1 X\n SG_ S : 0|8@1+ (0.1,0) [0|25.5] \"\" Y\n", "tenths.dbc");
  const std::uint8_t three[1] = {3};
  CHECK(bit_equal(0.3, decoded(tenths.messages[0].signals[0], three, 1)));
  CHECK_FALSE(bit_equal(0.3, 3 * 0.1));  // why the division matters
}

TEST(DbcReader, ExtendedIdsValueTablesCommentsAndReceiversAreRead) {
  const Dbc dbc = parse_dbc(kVehicle, "vehicle.dbc");
  LONGS_EQUAL(2, dbc.messages.size());
  const DbcMessage& cab = dbc.messages[0];
  CHECK(cab.extended);
  LONGS_EQUAL(0x0CFF1231, cab.id);
  STRCMP_EQUAL("Cab", cab.sender.c_str());
  STRCMP_EQUAL("Cab floor accelerometer", cab.comment.c_str());
  STRCMP_EQUAL("Vertical\nacceleration", cab.signals[0].comment.c_str());
  LONGS_EQUAL(2, cab.signals[0].receivers.size());
  STRCMP_EQUAL("Other", cab.signals[0].receivers[1].c_str());
  CHECK(dbc.find_message(0x0CFF1231, true) == &cab);
  CHECK(dbc.find_message(0x0CFF1231, false) == nullptr);
  const DbcSignal& door = signal_of(dbc, "Body", "Door");
  LONGS_EQUAL(2, door.value_names.size());
  STRCMP_EQUAL("open", door.value_names[1].second.c_str());
  LONGS_EQUAL(1, door.value_names[1].first);
  LONGS_EQUAL(18, door.line);
}

TEST(DbcReader, FrameTooShortForTheSignalHasNoValue) {
  const Dbc dbc = parse_dbc(kVehicle, "vehicle.dbc");
  const std::uint8_t data[1] = {0x7F};
  CHECK_FALSE(decode_signal(signal_of(dbc, "CabFloor", "AccZ"), data, 1).has_value());
}

TEST(DbcReader, MultiplexedSignalIsRefusedNamingTheLine) {
  STRCMP_EQUAL(
      "car.dbc:2: signal 'Sel' of message 'Mux' is multiplexed ('M'); multiplexed signals are "
      "not supported",
      error_of("BO_ 100 Mux: 8 X\n SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" Y\n"
               " SG_ Page m0 : 8|8@1+ (1,0) [0|255] \"\" Y\n")
          .c_str());
}

TEST(DbcReader, MultiplexedSignalIsRefusedEvenAfterPlainOnes) {
  STRCMP_EQUAL(
      "car.dbc:3: signal 'Page' of message 'Mux' is multiplexed ('m0'); multiplexed signals are "
      "not supported",
      error_of("BO_ 100 Mux: 8 X\n SG_ Plain : 0|8@1+ (1,0) [0|255] \"\" Y\n"
               " SG_ Page m0 : 8|8@1+ (1,0) [0|255] \"\" Y\n")
          .c_str());
}

TEST(DbcReader, MalformedStatementsAreNamedByFileAndLine) {
  STRCMP_EQUAL("car.dbc:2: expected '|', found ','",
               error_of("BO_ 1 M: 8 X\n SG_ S : 0,8@1+ (1,0) [0|1] \"\" Y\n").c_str());
  STRCMP_EQUAL("car.dbc:1: message id 2048 is beyond 11 bits (extended ids set bit 31)",
               error_of("BO_ 2048 M: 8 X\n").c_str());
  STRCMP_EQUAL("car.dbc:1: SG_ before any BO_ (a signal belongs to a message)",
               error_of(" SG_ S : 0|8@1+ (1,0) [0|1] \"\" Y\n").c_str());
  STRCMP_EQUAL("car.dbc:2: signal 'S' (start bit 510, 16 bits) runs beyond a 64-byte frame",
               error_of("BO_ 1 M: 8 X\n SG_ S : 510|16@1+ (1,0) [0|1] \"\" Y\n").c_str());
  STRCMP_EQUAL("car.dbc:2: VAL_: message 'M' has no signal 'T'",
               error_of("BO_ 1 M: 8 X\nVAL_ 1 T 0 \"a\" ;\n").c_str());
  STRCMP_EQUAL("car.dbc:1: string not closed by '\"'", error_of("CM_ \"open").c_str());
  // A unit's quote left open would swallow the lines after it up to the next quote (here the
  // next signal and its unit), attaching what follows to the wrong message: refused at its line.
  STRCMP_EQUAL("car.dbc:2: the unit string is not closed on its line (a '\"' is missing)",
               error_of("BO_ 1 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"m/s^2 Y\n"
                        " SG_ T : 8|8@1+ (1,0) [0|1] \"g\" Y\n")
                   .c_str());
  STRCMP_EQUAL("car.dbc:2: SIG_VALTYPE_: IEEE float signals are not supported",
               error_of("BO_ 1 M: 8 X\nSIG_VALTYPE_ 1 S : 1;\n").c_str());
}
