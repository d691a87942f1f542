// stickslip harmonic-balance: one row per K of the range, the balance marked valid exactly where
// K < 1.
#include <string>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

TEST_GROUP(HarmonicBalance){};

TEST(HarmonicBalance, CommandWritesTheComparison) {
  stickslip::test::TempDir dir;
  const stickslip::test::CliRun run =
      stickslip::test::run_stickslip({"harmonic-balance", "--k-range", "0:1.2:7", "--damping",
                                      "504", "--periods", "30", "--output", dir.file("hb.csv")});
  LONGS_EQUAL(0, run.status);
  const stickslip::test::Table table = stickslip::test::read_table(dir.file("hb.csv"));
  CHECK_TRUE(table.ok);
  LONGS_EQUAL(7, table.rows.size());
  STRCMP_EQUAL("hb_valid", table.header[3].c_str());
  for (const auto& row : table.rows) DOUBLES_EQUAL(row[1] < 1.0 ? 1.0 : 0.0, row[3], 0.0);
}
