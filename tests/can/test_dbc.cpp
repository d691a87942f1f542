// docs/can/stickslip.dbc matches the codec: a small DBC parser (BO_, SG_, VAL_) decodes frames
// the codec encoded, using only the DBC's start bits, lengths, byte order, signedness, factors and
// offsets, and every signal must come out as the codec decodes it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"

using namespace stickslip::can;

namespace {

struct DbcSignal {
  std::string name;
  int start_bit = 0;
  int length = 0;
  bool intel = true;  // @1: little endian
  bool is_signed = false;
  double factor = 1.0, offset = 0.0, minimum = 0.0, maximum = 0.0;
  std::string unit;
  std::map<long, std::string> values;  // VAL_
};

struct DbcMessage {
  std::uint32_t id = 0;
  std::string name;
  int length = 0;
  std::string transmitter;
  std::vector<DbcSignal> signals;
  const DbcSignal* find(const std::string& name_) const {
    for (const DbcSignal& s : signals)
      if (s.name == name_) return &s;
    return nullptr;
  }
};

struct Dbc {
  std::string version;
  std::vector<std::string> nodes;
  std::map<std::uint32_t, DbcMessage> messages;
};

// The text between the first pair of double quotes at or after `from`; `end` after the closing one.
bool quoted(const std::string& line, std::size_t from, std::string& text, std::size_t& end) {
  const std::size_t open = line.find('"', from);
  if (open == std::string::npos) return false;
  const std::size_t close = line.find('"', open + 1);
  if (close == std::string::npos) return false;
  text = line.substr(open + 1, close - open - 1);
  end = close + 1;
  return true;
}

// A line-based parser for the subset of DBC this project writes (sscanf, no std::regex: GCC 12
// warns inside <regex> under the sanitizer preset).
Dbc parse_dbc(const std::string& path) {
  Dbc dbc;
  std::ifstream in(path);
  CHECK_TRUE(in.good());
  std::string line;
  DbcMessage* current = nullptr;
  while (std::getline(in, line)) {
    std::size_t end = 0;
    if (line.rfind("VERSION", 0) == 0) {
      CHECK_TRUE(quoted(line, 0, dbc.version, end));
    } else if (line.rfind("BU_:", 0) == 0) {
      std::istringstream names(line.substr(4));
      for (std::string name; names >> name;) dbc.nodes.push_back(name);
    } else if (line.rfind("BO_ ", 0) == 0) {
      unsigned id = 0;
      int length = 0;
      char name[64] = {}, transmitter[64] = {};
      CHECK_EQUAL(4, std::sscanf(line.c_str(), "BO_ %u %63[^: ] : %d %63s", &id, name, &length,
                                 transmitter));
      current = &dbc.messages[id];
      current->id = id;
      current->name = name;
      current->length = length;
      current->transmitter = transmitter;
    } else if (line.rfind(" SG_ ", 0) == 0) {
      CHECK_TRUE(current != nullptr);
      DbcSignal s;
      char name[64] = {}, order = 0, sign = 0;
      int consumed = 0;
      const int fields = std::sscanf(line.c_str(), " SG_ %63s : %d|%d@%c%c (%lf,%lf) [%lf|%lf]%n",
                                     name, &s.start_bit, &s.length, &order, &sign, &s.factor,
                                     &s.offset, &s.minimum, &s.maximum, &consumed);
      CHECK_EQUAL(9, fields);
      CHECK_TRUE(order == '0' || order == '1');
      CHECK_TRUE(sign == '+' || sign == '-');
      s.name = name;
      s.intel = order == '1';
      s.is_signed = sign == '-';
      CHECK_TRUE(quoted(line, static_cast<std::size_t>(consumed), s.unit, end));
      CHECK_TRUE(line.find_first_not_of(' ', end) != std::string::npos);  // receivers
      current->signals.push_back(s);
    } else if (line.rfind("VAL_ ", 0) == 0) {
      unsigned id = 0;
      char name[64] = {};
      int consumed = 0;
      CHECK_EQUAL(2, std::sscanf(line.c_str(), "VAL_ %u %63s %n", &id, name, &consumed));
      DbcMessage& owner = dbc.messages.at(id);
      DbcSignal* target = nullptr;
      for (DbcSignal& s : owner.signals)
        if (s.name == name) target = &s;
      CHECK_TRUE(target != nullptr);
      const char* rest = line.c_str() + consumed;
      long value = 0;
      int used = 0;
      while (std::sscanf(rest, " %ld%n", &value, &used) == 1) {
        rest += used;
        std::string text;
        std::size_t after = 0;
        const std::string tail(rest);
        CHECK_TRUE(quoted(tail, 0, text, after));
        target->values[value] = text;
        rest += after;
      }
      CHECK_TRUE(std::string(rest).find(';') != std::string::npos);
    } else if (!line.empty() && line[0] != ' ' && line[0] != '\t') {
      current = nullptr;
    }
  }
  return dbc;
}

// The raw value of a signal from the 8 bytes, by the DBC's definition alone.
long dbc_raw(const DbcSignal& s, const std::uint8_t* data) {
  std::uint64_t word = 0;
  for (int i = 7; i >= 0; --i) word = (word << 8) | data[i];  // Intel: byte 0 is least significant
  const std::uint64_t mask = s.length == 64 ? ~0ull : ((1ull << s.length) - 1);
  const std::uint64_t bits = (word >> s.start_bit) & mask;
  if (s.is_signed && (bits >> (s.length - 1)) & 1u)
    return static_cast<long>(bits) - (1L << s.length);
  return static_cast<long>(bits);
}

double dbc_physical(const DbcSignal& s, const std::uint8_t* data) {
  return static_cast<double>(dbc_raw(s, data)) * s.factor + s.offset;
}

}  // namespace

TEST_GROUP(Dbc) {
  Dbc dbc;
  void setup() override {
    dbc = parse_dbc(STICKSLIP_DBC_PATH);
  }
};

TEST(Dbc, DescribesExactlyTheCodecsMessagesAndSignals) {
  CHECK_FALSE(dbc.version.empty());
  LONGS_EQUAL(2, dbc.nodes.size());
  LONGS_EQUAL(sizeof(kMessages) / sizeof(kMessages[0]), dbc.messages.size());
  for (const MessageSpec* spec : kMessages) {
    const auto found = dbc.messages.find(spec->id);
    CHECK_TRUE(found != dbc.messages.end());
    const DbcMessage& message = found->second;
    STRCMP_EQUAL(spec->name, message.name.c_str());
    LONGS_EQUAL(kPayloadLength, message.length);
    bool input = false;
    for (const MessageSpec* in : kInputMessages) input = input || in == spec;
    STRCMP_EQUAL(input ? "Host" : "ECU", message.transmitter.c_str());
    std::size_t expected = 5;  // CRC, AliveCounter, SampleCounter, two signals
    for (const char* flag : spec->flags) expected += flag != nullptr;
    LONGS_EQUAL(expected, message.signals.size());
    for (const DbcSignal& s : message.signals) CHECK_TRUE(s.intel);
    for (const SignalSpec& signal : spec->signals) {
      const DbcSignal* s = message.find(signal.name);
      CHECK_TRUE(s != nullptr);
      LONGS_EQUAL(16, s->length);
      CHECK_EQUAL(signal.is_signed, s->is_signed);
      CHECK_EQUAL(std::ldexp(1.0, -signal.fraction_bits), s->factor);  // exactly 2^-n
      CHECK_EQUAL(0.0, s->offset);
      STRCMP_EQUAL(signal.unit, s->unit.c_str());
      // [min|max] is the range quantise() produces; the not-available code has a VAL_ entry.
      const double top = (signal.is_signed ? kSignedMax : kUnsignedMax) * s->factor;
      CHECK_EQUAL(top, s->maximum);
      CHECK_EQUAL(signal.is_signed ? -top : 0.0, s->minimum);
      const long na = signal.is_signed ? kSignedNotAvailable : kUnsignedNotAvailable;
      CHECK_TRUE(s->values.count(na) == 1);
    }
  }
}

TEST(Dbc, DecodingCodecFramesWithTheDbcGivesTheCodecsValues) {
  std::mt19937_64 random(2024);
  std::uniform_real_distribution<double> spread(-1.2, 1.2);
  int checked = 0;
  for (const MessageSpec* spec : kMessages) {
    const DbcMessage& message = dbc.messages.at(spec->id);
    for (int trial = 0; trial < 2000; ++trial) {
      Payload payload;
      payload.sample_counter = static_cast<std::uint16_t>(random());
      payload.alive_counter = static_cast<std::uint8_t>(random() & 15u);
      payload.flags = static_cast<std::uint8_t>(random() & 15u);
      for (int j = 0; j < 2; ++j) {
        const SignalSpec& signal = spec->signals[j];
        const double full_scale =
            std::ldexp(signal.is_signed ? 32768.0 : 65536.0, -signal.fraction_bits);
        // Mostly in range, sometimes beyond (saturation), sometimes not available.
        const double value = trial % 97 == 0 ? std::nan("") : spread(random) * full_scale;
        payload.words[j] = quantise(signal, value).word;
      }
      std::uint8_t data[8];
      encode_payload(*spec, payload, data);

      LONGS_EQUAL(data[0], dbc_raw(*message.find("CRC"), data));
      LONGS_EQUAL(payload.alive_counter, dbc_raw(*message.find("AliveCounter"), data));
      LONGS_EQUAL(payload.sample_counter, dbc_raw(*message.find("SampleCounter"), data));
      for (int bit = 0; bit < 4; ++bit) {
        if (spec->flags[bit] == nullptr) continue;
        LONGS_EQUAL((payload.flags >> bit) & 1, dbc_raw(*message.find(spec->flags[bit]), data));
      }
      const Payload decoded = decode_payload(data);
      for (int j = 0; j < 2; ++j) {
        const SignalSpec& signal = spec->signals[j];
        const DbcSignal& s = *message.find(signal.name);
        const double codec_value = physical<double>(signal, decoded.words[j]);
        if (codec_value != codec_value) {
          const auto entry = s.values.find(dbc_raw(s, data));
          CHECK_TRUE(entry != s.values.end());
          STRCMP_EQUAL("not available", entry->second.c_str());
        } else {
          CHECK_EQUAL(codec_value, dbc_physical(s, data));
          CHECK(dbc_physical(s, data) >= s.minimum && dbc_physical(s, data) <= s.maximum);
        }
        ++checked;
      }
    }
  }
  LONGS_EQUAL(sizeof(kMessages) / sizeof(kMessages[0]) * 2000 * 2, checked);
}
