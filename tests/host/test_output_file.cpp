#include <string>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::AtomicOutputFile;
using stickslip::host::CsvWriter;
using stickslip::host::HostError;
using stickslip::test::TempDir;

// Output appears under its name only when complete; otherwise nothing is left behind.
TEST_GROUP(AtomicOutputFile) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

TEST(AtomicOutputFile, CommitRenamesTheCompleteFileIntoPlace) {
  const std::string path = dir.file("out.csv");
  {
    AtomicOutputFile file(path);
    file.write("hello\n");
    CHECK_FALSE(stickslip::test::exists(path));  // not visible before commit
    file.commit();
  }
  STRCMP_EQUAL("hello\n", stickslip::test::read_text(path).c_str());
  LONGS_EQUAL(1, dir.entries().size());
}

TEST(AtomicOutputFile, AnAbandonedFileLeavesNothing) {
  {
    AtomicOutputFile file(dir.file("out.csv"));
    file.write("partial");
  }
  LONGS_EQUAL(0, dir.entries().size());
}

TEST(AtomicOutputFile, AFailedRunKeepsTheOldFileIntact) {
  const std::string path = dir.file("out.csv");
  stickslip::test::write_text(path, "old\n");
  {
    AtomicOutputFile file(path);
    file.write("new, unfinished");
  }
  STRCMP_EQUAL("old\n", stickslip::test::read_text(path).c_str());
  LONGS_EQUAL(1, dir.entries().size());
}

TEST(AtomicOutputFile, AnImpossiblePathIsNamed) {
  const std::string path = dir.file("missing/out.csv");
  try {
    AtomicOutputFile file(path);
    FAIL("no error for a missing directory");
  } catch (const HostError& error) {
    STRCMP_EQUAL((path + ": cannot create the output file: No such file or directory").c_str(),
                 error.what());
  }
}

TEST_GROUP(CsvWriter) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

TEST(CsvWriter, WritesRowsAcrossManyBlocksInOrder) {
  const std::string path = dir.file("out.csv");
  {
    AtomicOutputFile file(path);
    CsvWriter writer(file, 64);  // tiny blocks: many flushes
    writer.text("x,flag\n");
    for (int n = 0; n < 1000; ++n) {
      writer.number(n * 0.5);
      writer.separator();
      writer.flag(n % 2 == 1);
      writer.end_row();
    }
    writer.flush();
    file.commit();
  }
  const auto lines = stickslip::test::split_lines(stickslip::test::read_text(path));
  LONGS_EQUAL(1001, lines.size());
  STRCMP_EQUAL("x,flag", lines[0].c_str());
  STRCMP_EQUAL("0,0", lines[1].c_str());
  STRCMP_EQUAL("0.5,1", lines[2].c_str());
  STRCMP_EQUAL("499.5,1", lines[1000].c_str());
}
