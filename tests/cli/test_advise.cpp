// stickslip advise (advise.hpp): the choice is the cheapest measured candidate inside the
// tolerance, its figures are the simulations', and the cheap model's failure at large K shows.
#include <cmath>
#include <string>

#include "stickslip/host/run/advise.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;
using stickslip::test::CliRun;
using stickslip::test::run_stickslip;

TEST_GROUP(Advise) {
  stickslip::test::TempDir dir;
  std::string lorry;
  void setup() override {
    CHECK_TRUE(dir.ok());
    lorry = dir.file("lorry.csv");
    LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                  "30", "--dt", "0.001", "--output", lorry})
                       .status);
  }
};

TEST(Advise, ChoosesTheCheapestCandidateWithinTheTolerance) {
  for (double friction : {5.0, 45.0}) {
    AdviseRequest request;
    request.input_path = lorry;
    request.params.kinetic_friction_n = request.params.static_friction_n = friction;
    request.tolerance = 0.01;
    const AdviseReport report = advise(request);
    DOUBLES_EQUAL(0.35, report.a0u, 1e-9);
    DOUBLES_EQUAL(4.0 * friction / (3.14159265358979323846 * std::sqrt(2.0) * 88.4 * 0.35),
                  report.k, 1e-9);
    CHECK_TRUE(report.chosen >= 0);
    const AdviseCandidate& chosen = report.candidates[static_cast<std::size_t>(report.chosen)];
    CHECK_TRUE(chosen.configured);
    CHECK_TRUE(chosen.relative_error <= 0.01);
    bool reference_listed = false;
    for (std::size_t i = 0; i < report.candidates.size(); ++i) {
      const AdviseCandidate& c = report.candidates[i];
      if (c.model == FrictionModel::stick_slip && c.integrator == Integrator::exact) {
        reference_listed = true;
        DOUBLES_EQUAL(0.0, c.relative_error, 0.0);
      }
      if (c.configured) {
        DOUBLES_EQUAL(std::fabs(c.transmissibility / report.reference.transmissibility - 1.0),
                      c.relative_error, 1e-15);
      }
      // Nothing clearly cheaper (beyond the 10 % tie band) was within the tolerance.
      if (c.configured && c.ns_per_sample * 1.1 < chosen.ns_per_sample)
        CHECK_FALSE(c.within_tolerance);
    }
    CHECK_TRUE(reference_listed);
  }
}

// K = 1.3 on the lorry scene: signum on ode1 chatters instead of sticking and misses T_ax by
// far more than 1 %; the stick-slip model sticks most of the time.
TEST(Advise, CommandShowsTheCheapModelsErrorAtLargeK) {
  const CliRun run = run_stickslip({"advise", "--input", lorry, "--ffk", "45"});
  LONGS_EQUAL(0, run.status);
  STRCMP_CONTAINS("K = 1.309 (stick-slip required)", run.out.c_str());
  STRCMP_CONTAINS("cheap model signum/euler", run.out.c_str());
  STRCMP_CONTAINS("advice: ", run.out.c_str());
  AdviseRequest request;
  request.input_path = lorry;
  request.params.kinetic_friction_n = request.params.static_friction_n = 45.0;
  const AdviseReport report = advise(request);
  CHECK_TRUE(report.cheap.relative_error > 0.2);
  CHECK_TRUE(report.reference.stick_probability > 0.5);
  DOUBLES_EQUAL(0.0, report.cheap.stick_probability, 0.0);  // signum never reports stuck
  const CliRun bad = run_stickslip({"advise", "--input", lorry, "--ffk", "45", "--tolerance", "0"});
  LONGS_EQUAL(2, bad.status);
  STRCMP_CONTAINS("--tolerance: must be > 0", bad.err.c_str());
}
