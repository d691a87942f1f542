// Ctrl-C (SIGINT) or SIGTERM while a command writes: the real executable in a child process,
// signalled once its temporary output exists. Nothing may be left behind (no ".NAME.tmpPID-N"),
// an existing output keeps its contents, and one line says what happened; the status is
// 128 + the signal.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::read_text;
using stickslip::test::run_stickslip;
using stickslip::test::split_lines;
using stickslip::test::TempDir;

namespace {

struct Interrupted {
  int status = -1;  // the exit status, or -1 if the child did not exit on its own
  bool saw_temporary = false;
  std::string err;
};

bool has_temporary(const TempDir& dir) {
  for (const std::string& name : dir.entries())
    if (name.find(".tmp") != std::string::npos) return true;
  return false;
}

// Runs stickslip with `arguments` in the child, waits for a temporary output in `dir`, then sends
// `signal_number` at once: on a busy machine that often lands just as the file is created.
Interrupted run_and_interrupt(const TempDir& dir, std::vector<std::string> arguments,
                              int signal_number) {
  Interrupted result;
  const std::string err_path = dir.file("stderr.txt");
  arguments.insert(arguments.begin(), STICKSLIP_EXECUTABLE);
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  if (child == 0) {
    if (std::freopen(err_path.c_str(), "w", stderr) == nullptr ||
        std::freopen("/dev/null", "w", stdout) == nullptr)
      ::_exit(99);
    ::execv(argv[0], argv.data());
    ::_exit(98);
  }
  for (int i = 0; i < 2000 && !result.saw_temporary; ++i) {
    result.saw_temporary = has_temporary(dir);
    if (!result.saw_temporary) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(child, signal_number);
  int status = 0;
  ::waitpid(child, &status, 0);
  if (WIFEXITED(status)) result.status = WEXITSTATUS(status);
  result.err = read_text(err_path);
  ::unlink(err_path.c_str());
  return result;
}

}  // namespace

TEST_GROUP(Interrupt) {
  TempDir dir;
  std::string in;
  void setup() override {
    CHECK_TRUE(dir.ok());
    in = dir.file("long.csv");
    // 600 s at 1 ms: long enough that the signal comes while the command still runs.
    LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                  "600", "--dt", "0.001", "--output", in})
                       .status);
  }
};

TEST(Interrupt, CtrlCDuringSweepLeavesNoTemporaryAndKeepsTheExistingOutput) {
  const std::string out = dir.file("sweep.csv");
  stickslip::test::write_text(out, "the previous sweep\n");
  const Interrupted run =
      run_and_interrupt(dir,
                        {"sweep", "--input", in, "--damping", "504", "--k-range", "0.1:3:400",
                         "--threads", "1", "--quiet", "--output", out},
                        SIGINT);
  CHECK_TRUE(run.saw_temporary);
  LONGS_EQUAL(130, run.status);
  LONGS_EQUAL(1, split_lines(run.err).size());
  STRCMP_CONTAINS("stickslip: interrupted by SIGINT: ", run.err.c_str());
  STRCMP_CONTAINS(" points done, nothing written", run.err.c_str());
  CHECK_FALSE(has_temporary(dir));
  STRCMP_EQUAL("the previous sweep\n", read_text(out).c_str());
}

TEST(Interrupt, SigtermDuringSimulateWithStatsLeavesNoTemporary) {
  const Interrupted run =
      run_and_interrupt(dir,
                        {"simulate", "--input", in, "--output", dir.file("o.csv"), "--stats",
                         dir.file("o.json"), "--model", "stribeck", "--repetitions", "50"},
                        SIGTERM);
  CHECK_TRUE(run.saw_temporary);
  LONGS_EQUAL(143, run.status);
  STRCMP_EQUAL("stickslip: interrupted by SIGTERM, nothing written (existing outputs kept)\n",
               run.err.c_str());
  CHECK_FALSE(has_temporary(dir));
  CHECK_FALSE(stickslip::test::exists(dir.file("o.csv")));
  CHECK_FALSE(stickslip::test::exists(dir.file("o.json")));
}
