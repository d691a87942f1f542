// The delimited text reader (sim_host/src/io/delimited_text.cpp) on files as loggers write them:
// separators, decimal commas, banners, BOM, CRLF, units in the header; and today's t,a_u CSV,
// which must read to the very doubles CsvReader gives.
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/delimited_text.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::DelimitedTable;
using stickslip::host::HostError;
using stickslip::host::parse_delimited_text;
using stickslip::host::read_delimited_text;
using stickslip::host::split_name_and_unit;
using stickslip::test::bit_equal;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

std::string error_of(const std::string& text, const std::string& name = "in.csv") {
  try {
    parse_delimited_text(text, name);
  } catch (const HostError& error) {
    return error.what();
  }
  return "(no error)";
}

}  // namespace

TEST_GROUP(DelimitedText){};

TEST(DelimitedText, TodaysCsvReadsToTheSameDoublesAsCsvReader) {
  TempDir dir;
  CHECK(dir.ok());
  std::string text = "t,a_u\n";
  char line[96];
  for (int n = 0; n < 500; ++n) {
    const double t = n * 0.001;
    const double a_u = 3.7 * static_cast<double>((n * 7919) % 1000 - 500) / 997.0;
    std::snprintf(line, sizeof line, n % 3 == 0 ? "%.17g,%.17g\n" : "%.6f,%+.9e\n", t, a_u);
    text += line;
  }
  text += "0.5,1e-3\n0.501,-0\n";
  const std::string path = dir.file("today.csv");
  write_text(path, text);
  const stickslip::host::SampledSignal expected = stickslip::host::read_signal_csv(path);
  const DelimitedTable table = read_delimited_text(path);
  CHECK_EQUAL(',', table.separator);
  CHECK_EQUAL('.', table.decimal_mark);
  LONGS_EQUAL(1, table.header_line);
  const auto& t = table.channel("t").values;
  const auto& a_u = table.channel("a_u").values;
  LONGS_EQUAL(expected.t_s.size(), t.size());
  LONGS_EQUAL(expected.a_u_m_per_s2.size(), a_u.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    CHECK(bit_equal(expected.t_s[i], t[i]));
    CHECK(bit_equal(expected.a_u_m_per_s2[i], a_u[i]));
  }
}

TEST(DelimitedText, SemicolonsWithDecimalCommasUnderABannerAndBom) {
  const DelimitedTable table = parse_delimited_text(
      "\xEF\xBB\xBFMSR145 data logger, serial 4711\r\n"
      "# exported 2026-11-25 12:00\r\n"
      "\r\n"
      "Time [s];AccZ [g];Temp (degC)\r\n"
      "0,000;0,012;21,5\r\n"
      "0,002;-0,5;21,5\r\n"
      "0,004;1,25e-1;21,625\r\n",
      "logger.csv");
  CHECK_EQUAL(';', table.separator);
  CHECK_EQUAL(',', table.decimal_mark);
  LONGS_EQUAL(4, table.header_line);
  LONGS_EQUAL(5, table.first_data_line);
  LONGS_EQUAL(3, table.channels.size());
  STRCMP_EQUAL("Time", table.channels[0].name.c_str());
  STRCMP_EQUAL("s", table.channels[0].unit.c_str());
  STRCMP_EQUAL("AccZ", table.channels[1].name.c_str());
  STRCMP_EQUAL("g", table.channels[1].unit.c_str());
  STRCMP_EQUAL("degC", table.channels[2].unit.c_str());
  const std::vector<double> accz = table.channel("AccZ").values;
  LONGS_EQUAL(3, accz.size());
  CHECK(bit_equal(0.012, accz[0]));
  CHECK(bit_equal(-0.5, accz[1]));
  CHECK(bit_equal(0.125, accz[2]));
  CHECK(bit_equal(0.004, table.channel("1").values[2]));
}

TEST(DelimitedText, TabsWithUnitsInParenthesesAndBrackets) {
  const DelimitedTable table = parse_delimited_text(
      "t (s)\ta_u (m/s^2)\tAccZ[mm/s\xC2\xB2]\n0.1\t2.5\t-3\n0.2\t2.75\t4\n", "tabs.txt");
  CHECK_EQUAL('\t', table.separator);
  STRCMP_EQUAL("a_u", table.channels[1].name.c_str());
  STRCMP_EQUAL("m/s^2", table.channels[1].unit.c_str());
  STRCMP_EQUAL("AccZ", table.channels[2].name.c_str());
  STRCMP_EQUAL("mm/s\xC2\xB2", table.channels[2].unit.c_str());
  CHECK(bit_equal(2.75, table.channel("a_u").values[1]));
}

TEST(DelimitedText, TabsWithDecimalCommas) {
  const DelimitedTable table = parse_delimited_text("t\tx\n0,5\t1,5\n1,0\t-2,25\n", "tabs.txt");
  CHECK_EQUAL('\t', table.separator);
  CHECK_EQUAL(',', table.decimal_mark);
  CHECK(bit_equal(-2.25, table.channel("x").values[1]));
}

// Many European exports end every line, header included, with the separator: it closes the last
// cell. A row that then has fewer cells than the header is still named.
TEST(DelimitedText, ASeparatorEndingEveryLineClosesTheLastCell) {
  const DelimitedTable table =
      parse_delimited_text("Time [s];AccZ [g];\n0,000;0,012;\n0,002;-0,5;\n", "export.csv");
  CHECK_EQUAL(';', table.separator);
  LONGS_EQUAL(2, table.channels.size());
  STRCMP_EQUAL("AccZ", table.channels[1].name.c_str());
  CHECK(bit_equal(-0.5, table.channel("AccZ").values[1]));
  STRCMP_EQUAL("in.csv:3: expected 3 fields separated by ',' like line 2, found 2",
               error_of("t,a_u,x\n0,1,2\n0.001,2,\n").c_str());
}

TEST(DelimitedText, BlankSeparatedWithoutHeaderIsSelectedByIndex) {
  const DelimitedTable table =
      parse_delimited_text("% acquisition banner\n  0.000   1.5\n  0.001  -1.5\n", "raw.dat");
  CHECK_EQUAL(' ', table.separator);
  LONGS_EQUAL(0, table.header_line);
  STRCMP_EQUAL("column 2", table.channels[1].name.c_str());
  CHECK(bit_equal(-1.5, table.channel("2").values[1]));
}

TEST(DelimitedText, NamesMatchIgnoringCaseAndUnknownNamesListTheColumns) {
  const DelimitedTable table = parse_delimited_text("Time [s],AccZ [g]\n0,1\n1,2\n", "a.csv");
  CHECK(bit_equal(2.0, table.channel("accz").values[1]));
  try {
    table.channel("a_u");
    FAIL("expected a HostError");
  } catch (const HostError& error) {
    STRCMP_EQUAL("a.csv: no column 'a_u' (the columns: 1 'Time' [s], 2 'AccZ' [g])", error.what());
  }
}

TEST(DelimitedText, BadCellIsNamedByFileLineAndColumn) {
  STRCMP_EQUAL("in.csv:4: column 2: 'abc' is not a number (decimal mark '.')",
               error_of("t,a_u\n0,1\n0.001,2\n0.002,abc\n0.003,4\n").c_str());
}

TEST(DelimitedText, RaggedRowIsNamedByFileAndLine) {
  STRCMP_EQUAL("in.csv:3: expected 2 fields separated by ',' like line 2, found 3",
               error_of("t,a_u\n0,1\n0.001,2,3\n").c_str());
}

TEST(DelimitedText, NonFiniteValueIsRefused) {
  STRCMP_EQUAL("in.csv:3: column 2: 'inf' is not a finite number",
               error_of("t,a_u\n0,1\n0.001,inf\n").c_str());
}

TEST(DelimitedText, FileWithoutNumbersIsRefused) {
  STRCMP_EQUAL(
      "in.csv: no rows of numbers (expected a table separated by ',', ';', tab or blanks, under "
      "an optional header line)",
      error_of("just a banner\n").c_str());
  STRCMP_EQUAL(
      "in.csv: no rows of numbers (expected a table separated by ',', ';', tab or blanks, under "
      "an optional header line)",
      error_of("").c_str());
}

TEST(DelimitedText, DuplicateColumnNamesAreRefused) {
  STRCMP_EQUAL("in.csv:1: column 'x' appears twice in the header",
               error_of("x [m],x [g]\n1,2\n").c_str());
}

TEST(DelimitedText, HeaderCellsSplitIntoNameAndUnit) {
  STRCMP_EQUAL("Time", split_name_and_unit("Time [s]").name.c_str());
  STRCMP_EQUAL("s", split_name_and_unit("Time [s]").unit.c_str());
  STRCMP_EQUAL("a_u", split_name_and_unit("\"a_u (m/s^2)\"").name.c_str());
  STRCMP_EQUAL("m/s^2", split_name_and_unit("\"a_u (m/s^2)\"").unit.c_str());
  STRCMP_EQUAL("t", split_name_and_unit(" t ").name.c_str());
  STRCMP_EQUAL("", split_name_and_unit("t").unit.c_str());
  STRCMP_EQUAL("[g]", split_name_and_unit("[g]").name.c_str());
}
