// docs/can/stickslip.dbc as canmatrix (python3-canmatrix) reads it: it loads, and its E2E
// attributes, "not available" raw values and flag value tables are the codec's.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "stickslip/can/codec.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip::can;

namespace {

// What canmatrix makes of the DBC, as JSON: per message its attributes, per signal its
// attributes and value table.
constexpr const char* kDump = R"PY(
import json, sys
import canmatrix.formats
db = canmatrix.formats.loadp_flat(sys.argv[1])
out = {}
for frame in db.frames:
    out[str(frame.arbitration_id.id)] = {
        "attributes": {k: str(v) for k, v in frame.attributes.items()},
        "signals": {s.name: {"attributes": {k: str(v) for k, v in s.attributes.items()},
                             "values": {str(k): v for k, v in s.values.items()}}
                    for s in frame.signals}}
out["defaults"] = {k: str(db.frame_defines[k].defaultValue) for k in db.frame_defines}
print(json.dumps(out))
)PY";

}  // namespace

TEST_GROUP(DbcCanmatrix){};

TEST(DbcCanmatrix, LoadsTheDbcWithTheCodecsE2eAttributesAndNotAvailableCodes) {
  if (std::system("/usr/bin/python3 -c 'import canmatrix' >/dev/null 2>&1") != 0) {
    std::printf("\nSKIPPED: canmatrix not found (Debian package python3-canmatrix)\n");
    return;
  }
  stickslip::test::TempDir dir;
  const std::string script = dir.file("dump.py"), dump = dir.file("dump.json");
  stickslip::test::write_text(script, kDump);
  const std::string command =
      "/usr/bin/python3 '" + script + "' '" STICKSLIP_DBC_PATH "' >'" + dump + "' 2>/dev/null";
  LONGS_EQUAL(0, std::system(command.c_str()));
  const auto db = nlohmann::json::parse(stickslip::test::read_text(dump));

  // The CRC rule: polynomial 0x1D, init and final XOR 0xFF (crc8.hpp), as the defaults.
  STRCMP_EQUAL("29", db["defaults"]["E2ECrcPolynomial"].get<std::string>().c_str());
  STRCMP_EQUAL("255", db["defaults"]["E2ECrcInit"].get<std::string>().c_str());
  STRCMP_EQUAL("255", db["defaults"]["E2ECrcXorOut"].get<std::string>().c_str());
  for (const MessageSpec* spec : kMessages) {
    const auto& message = db[std::to_string(spec->id)];
    STRCMP_EQUAL(std::to_string(spec->data_id).c_str(),
                 message["attributes"]["E2EDataID"].get<std::string>().c_str());
    const auto& signals = message["signals"];
    STRCMP_EQUAL("Crc", signals["CRC"]["attributes"]["E2ESignal"].get<std::string>().c_str());
    STRCMP_EQUAL(
        "16", signals["AliveCounter"]["attributes"]["E2ECounterModulo"].get<std::string>().c_str());
    STRCMP_EQUAL(
        "65536",
        signals["SampleCounter"]["attributes"]["E2ECounterModulo"].get<std::string>().c_str());
    for (const SignalSpec& signal : spec->signals) {
      const long na = signal.is_signed ? kSignedNotAvailable : kUnsignedNotAvailable;
      const auto& s = signals[signal.name];
      STRCMP_EQUAL(std::to_string(na).c_str(),
                   s["attributes"]["NotAvailableRaw"].get<std::string>().c_str());
      STRCMP_EQUAL("not available", s["values"][std::to_string(na)].get<std::string>().c_str());
    }
    // Every flag the codec sends has a value table for 0 and 1.
    for (const char* flag : spec->flags) {
      if (flag == nullptr) continue;
      const auto& values = signals[flag]["values"];
      CHECK_TRUE(values.contains("0") && values.contains("1"));
    }
  }
}
