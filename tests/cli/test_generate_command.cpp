// stickslip generate: the same seed gives the same bytes on every machine, one row per sample
// at the requested RMS, and invalid requests are refused without writing a file.
#include <cmath>
#include <string>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

namespace {

double rms(const std::vector<double>& x) {
  long double sum = 0.0L;
  for (double v : x) sum += static_cast<long double>(v) * static_cast<long double>(v);
  return static_cast<double>(std::sqrt(sum / static_cast<long double>(x.size())));
}

}  // namespace

TEST_GROUP(Generator) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }

  CliRun generate(const std::string& kind, const std::string& seed, const std::string& file,
                  const std::string& duration = "20", const std::string& dt = "0.001") {
    return run_stickslip({"generate", "--kind", kind, "--rms", "0.35", "--duration", duration,
                          "--dt", dt, "--seed", seed, "--frequency", "3", "--output",
                          dir.file(file)});
  }
};

TEST(Generator, SameSeedGivesIdenticalBytesAndAnotherSeedDifferent) {
  for (const char* kind : {"wideband", "lorry"}) {
    LONGS_EQUAL(0, generate(kind, "42", "a.csv").status);
    LONGS_EQUAL(0, generate(kind, "42", "b.csv").status);
    LONGS_EQUAL(0, generate(kind, "43", "c.csv").status);
    const std::string a = stickslip::test::read_text(dir.file("a.csv"));
    CHECK_TRUE(a.size() > 100000);
    CHECK_TRUE(a == stickslip::test::read_text(dir.file("b.csv")));
    CHECK_FALSE(a == stickslip::test::read_text(dir.file("c.csv")));
  }
}

// Pins the exact bytes: with our own PRNG, Gaussian, log/sin/cos and filters (no libm, no
// <random>, no FMA) these are the same on every machine; a change here changes recordings.
TEST(Generator, FilesAreTheSameOnEveryMachine) {
  LONGS_EQUAL(0, generate("wideband", "1", "w.csv", "2", "0.01").status);
  LONGS_EQUAL(0, generate("lorry", "1", "l.csv", "2", "0.01").status);
  LONGS_EQUAL(0, generate("harmonic", "1", "h.csv", "2", "0.01").status);
  const auto head = [&](const std::string& file) {
    return stickslip::test::split_lines(stickslip::test::read_text(dir.file(file))).at(2);
  };
  STRCMP_EQUAL("0.01,-0.50191113273326415", head("w.csv").c_str());
  STRCMP_EQUAL("0.01,0.90352844981386005", head("l.csv").c_str());
  STRCMP_EQUAL("0.01,0.092980602176382196", head("h.csv").c_str());
  CHECK_EQUAL(16209717020812864016ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("w.csv"))));
  CHECK_EQUAL(18264029936581452316ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("l.csv"))));
  CHECK_EQUAL(5705278269092566359ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("h.csv"))));
}

TEST(Generator, WritesOneRowPerSampleWithTFromTheIndexAndTheRequestedRms) {
  for (const char* kind : {"wideband", "lorry", "harmonic"}) {
    const CliRun run = generate(kind, "5", "g.csv", "12.3456", "0.001");
    LONGS_EQUAL(0, run.status);
    STRCMP_EQUAL("", run.err.c_str());
    const stickslip::test::Table table = stickslip::test::read_table(dir.file("g.csv"));
    CHECK_TRUE(table.ok);
    LONGS_EQUAL(2, table.header.size());
    STRCMP_EQUAL("t", table.header[0].c_str());
    STRCMP_EQUAL("a_u", table.header[1].c_str());
    LONGS_EQUAL(12347, table.rows.size());  // n = 0..round(12.3456/0.001) = 12346
    for (std::size_t n = 0; n < table.rows.size(); ++n) {
      CHECK_TRUE(stickslip::test::bit_equal(static_cast<double>(n) * 0.001, table.rows[n][0]));
    }
    const double measured = rms(stickslip::test::column(table, 1));
    DOUBLES_EQUAL(0.35, measured, 0.35 * 1e-12);
  }
}

TEST(Generator, InvalidRequestsAreRefusedWithoutAFile) {
  struct Case {
    std::vector<std::string> arguments;
    const char* message;
  };
  const std::string out = dir.file("bad.csv");
  const Case cases[] = {
      {{"--kind", "pink", "--rms", "1", "--duration", "1", "--dt", "0.001"},
       "--kind: unknown kind 'pink'"},
      {{"--kind", "pink", "--duration", "1", "--dt", "0.001"}, "--kind: unknown kind 'pink'"},
      {{"--kind", "wideband", "--duration", "1", "--dt", "0.001"}, "--rms is required"},
      {{"--kind", "wideband", "--rms", "0", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got 0"},
      {{"--kind", "wideband", "--rms", "-1", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got -1"},
      {{"--kind", "white", "--rms", "inf", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got inf"},
      {{"--kind", "white", "--rms", "nan", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got nan"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "0", "--dt", "0.001"},
       "--duration: must be a finite number > 0"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1", "--dt", "0"},
       "--dt: must be a finite number > 0"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "0.0001", "--dt", "0.001"},
       "shorter than one step"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1e7", "--dt", "1e-3"},
       "more than the limit"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "10", "--dt", "0.03"},
       "--dt: wideband needs 0.5/dt above 20 Hz"},
      {{"--kind", "lorry", "--rms", "1", "--duration", "10", "--dt", "0.03"},
       "--dt: lorry needs 0.5/dt above 20 Hz"},
      {{"--kind", "harmonic", "--rms", "1", "--duration", "1", "--dt", "0.001"},
       "--frequency: harmonic needs 0 < frequency < 0.5/dt = 500 Hz, got 0"},
      {{"--kind", "harmonic", "--rms", "1", "--duration", "1", "--dt", "0.001", "--frequency",
        "500"},
       "--frequency: harmonic needs"},
      {{"--kind", "wideband", "--rms", "abc", "--duration", "1", "--dt", "0.001"}, "--rms"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1"}, "--dt is required"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> arguments{"generate"};
    arguments.insert(arguments.end(), c.arguments.begin(), c.arguments.end());
    arguments.insert(arguments.end(), {"--output", out});
    const CliRun run = run_stickslip(arguments);
    LONGS_EQUAL(2, run.status);
    STRCMP_CONTAINS(c.message, run.err.c_str());
    STRCMP_CONTAINS("stickslip: ", run.err.c_str());
    LONGS_EQUAL(1, stickslip::test::split_lines(run.err).size());
    LONGS_EQUAL(0, dir.entries().size());
  }
}
