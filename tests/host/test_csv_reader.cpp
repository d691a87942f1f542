#include <filesystem>
#include <string>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::HostError;
using stickslip::host::read_signal_csv;
using stickslip::host::SampledSignal;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {
// The message of the HostError that reading `text` as a signal throws ("" if none).
std::string read_error(const TempDir& dir, const std::string& text) {
  const std::string path = dir.file("in.csv");
  write_text(path, text);
  try {
    read_signal_csv(path);
  } catch (const HostError& error) {
    return error.what();
  }
  return "";
}
}  // namespace

TEST_GROUP(CsvReader) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
  std::string path() const {
    return dir.file("in.csv");
  }
};

TEST(CsvReader, ReadsTAndAuAndIgnoresOtherColumnsInAnyOrder) {
  write_text(path(), "a_u,note,t\n1.5,7,0\n-2.25,8,0.5\n3,9,1\n");
  const SampledSignal signal = read_signal_csv(path());
  LONGS_EQUAL(3, signal.t_s.size());
  DOUBLES_EQUAL(-2.25, signal.a_u_m_per_s2[1], 0.0);
  DOUBLES_EQUAL(1.0, signal.t_s[2], 0.0);
  DOUBLES_EQUAL(0.5, signal.dt_s, 0.0);
}

TEST(CsvReader, AcceptsCrLfSpacesPlusSignsBomAndNoFinalNewline) {
  write_text(path(), "\xEF\xBB\xBF t , a_u \r\n0, +1e-3\r\n 0.25 ,2\r\n\r\n0.5,3");
  const SampledSignal signal = read_signal_csv(path());
  LONGS_EQUAL(3, signal.t_s.size());
  DOUBLES_EQUAL(1e-3, signal.a_u_m_per_s2[0], 0.0);
  DOUBLES_EQUAL(3.0, signal.a_u_m_per_s2[2], 0.0);
  DOUBLES_EQUAL(0.25, signal.dt_s, 0.0);
}

TEST(CsvReader, ReadsFilesLargerThanItsBlockExactly) {
  // ~6 MB: lines straddle the reader's 4 MiB block boundary.
  std::string text = "t,a_u\n";
  const int rows = 250000;
  for (int n = 0; n < rows; ++n) {
    text += std::to_string(n) + ",0.1234567890123456" + std::to_string(n % 10) + "\n";
  }
  write_text(path(), text);
  const SampledSignal signal = read_signal_csv(path());
  LONGS_EQUAL(rows, signal.t_s.size());
  for (int n = 0; n < rows; ++n) {
    DOUBLES_EQUAL(static_cast<double>(n), signal.t_s[static_cast<std::size_t>(n)], 0.0);
  }
  DOUBLES_EQUAL(0.12345678901234569, signal.a_u_m_per_s2[249999], 0.0);
  DOUBLES_EQUAL(1.0, signal.dt_s, 0.0);
}

TEST(CsvReader, ToleratesRoundingInTButNotAnIrregularStep) {
  write_text(path(), "t,a_u\n0,0\n0.0010000000001,0\n0.002,0\n");  // 1e-7 relative: accepted
  LONGS_EQUAL(3, read_signal_csv(path()).t_s.size());
  STRCMP_CONTAINS("in.csv:4: column 't': t is not uniform",
                  read_error(dir, "t,a_u\n0,0\n0.001,0\n0.0020001,0\n").c_str());
}

TEST(CsvReader, EveryProblemNamesFileLineAndColumn) {
  const std::string p = path();
  STRCMP_EQUAL((p + ":1: the file is empty; expected a header line naming the columns").c_str(),
               read_error(dir, "").c_str());
  STRCMP_EQUAL((p + ":1: missing column 'a_u' (the header names: t,x)").c_str(),
               read_error(dir, "t,x\n0,1\n1,2\n").c_str());
  STRCMP_EQUAL((p + ":3: column 'a_u': 'abc' is not a number").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,abc\n").c_str());
  STRCMP_EQUAL((p + ":2: column 't': '1.5.2' is not a number").c_str(),
               read_error(dir, "t,a_u\n1.5.2,1\n2,1\n").c_str());
  STRCMP_EQUAL((p + ":3: column 'a_u': 'nan' is not a finite number").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,nan\n").c_str());
  STRCMP_EQUAL((p + ":4: column 'a_u': '-inf' is not a finite number").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,2\n2,-inf\n").c_str());
  STRCMP_EQUAL((p + ":3: column 'a_u': '1e999' is out of the range of a double").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,1e999\n").c_str());
  STRCMP_EQUAL((p + ":3: column 'a_u': empty cell, expected a number").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,\n").c_str());
  STRCMP_EQUAL((p + ":3: expected 2 fields like the header (t,a_u), found 3").c_str(),
               read_error(dir, "t,a_u\n0,1\n1,2,3\n").c_str());
  STRCMP_EQUAL((p + ":1: no samples after the header; at least 2 are needed").c_str(),
               read_error(dir, "t,a_u\n").c_str());
  STRCMP_EQUAL((p + ":2: only 1 sample after the header; at least 2 are needed").c_str(),
               read_error(dir, "t,a_u\n0,1\n").c_str());
  STRCMP_EQUAL((p + ":3: column 't': t must increase, got 0 after 1").c_str(),
               read_error(dir, "t,a_u\n1,1\n0,1\n").c_str());
  STRCMP_EQUAL((p + ":1: column 't' appears twice in the header").c_str(),
               read_error(dir, "t,a_u,t\n0,1,0\n1,1,1\n").c_str());
  STRCMP_EQUAL((p + ":1: the header line is empty; expected column names such as t,a_u").c_str(),
               read_error(dir, "\n0,1\n").c_str());
}

TEST(CsvReader, LineNumbersCountBlankLines) {
  STRCMP_EQUAL((path() + ":5: column 'a_u': 'x' is not a number").c_str(),
               read_error(dir, "t,a_u\n0,1\n\n1,2\n2,x\n").c_str());
}

TEST(CsvReader, MissingFileAndDirectoryAreNamed) {
  try {
    read_signal_csv(dir.file("absent.csv"));
    FAIL("no error for a missing file");
  } catch (const HostError& error) {
    STRCMP_EQUAL((dir.file("absent.csv") + ": cannot open: No such file or directory").c_str(),
                 error.what());
  }
  try {
    read_signal_csv(dir.file(""));
    FAIL("no error for a directory");
  } catch (const HostError& error) {
    STRCMP_CONTAINS("it is a directory", error.what());
  }
}

// t values that are finite but whose step is not (found by fuzz/fuzz_csv_reader.cpp's invariant
// dt finite): refused naming the column, without raising an overflow on the way.
TEST(CsvReader, RefusesAStepBeyondTheRangeOfADouble) {
  const std::string message = read_error(dir, "t,a_u\n-1e308,0\n1e308,1\n");
  STRCMP_CONTAINS("in.csv:2: column 't': -1e+308 is beyond the time range", message.c_str());
}

// A refused file is closed (the constructor threw before its destructor could: found by fuzzing,
// each refused header leaked a FILE until the process ran out of descriptors).
TEST(CsvReader, RefusedFilesAreClosed) {
  auto open_descriptors = [] {
    std::size_t count = 0;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
      (void)entry;
      ++count;
    }
    return count;
  };
  const std::size_t before = open_descriptors();
  const char* const refused[] = {"", "\n", "t,t\n0,1\n", "t,a_u\n", "a_u\n1\n2\n", "t,a_u\n0,x\n"};
  for (int round = 0; round < 20; ++round)
    for (const char* text : refused) CHECK_FALSE(read_error(dir, text).empty());
  UNSIGNED_LONGS_EQUAL(before, open_descriptors());
}
