#include <cstddef>
#include <cstdint>

#include "stickslip/host/run/simulation.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::StepOutput;
using stickslip::host::SimulationTrace;

namespace {

// A trace of `rows` rows whose every value tells its column and row apart from any other's.
SimulationTrace<double> numbered_trace(std::size_t rows, double first) {
  SimulationTrace<double> trace;
  trace.resize(rows);
  for (std::size_t row = 0; row < rows; ++row) {
    const double n = first + static_cast<double>(row);
    StepOutput<double> out{};
    out.x_r_m = n;
    out.v_r_m_per_s = 1000.0 + n;
    out.a_x_m_per_s2 = 2000.0 + n;
    out.friction_n = 3000.0 + n;
    out.stuck = row % 2 == 1;
    trace.store(row, out);
  }
  return trace;
}

void check_row(const SimulationTrace<double>& trace, std::size_t row,
               const SimulationTrace<double>& part, std::size_t part_row) {
  DOUBLES_EQUAL(part.x_r_m[part_row], trace.x_r_m[row], 0.0);
  DOUBLES_EQUAL(part.v_r_m_per_s[part_row], trace.v_r_m_per_s[row], 0.0);
  DOUBLES_EQUAL(part.a_x_m_per_s2[part_row], trace.a_x_m_per_s2[row], 0.0);
  DOUBLES_EQUAL(part.friction_n[part_row], trace.friction_n[row], 0.0);
  UNSIGNED_LONGS_EQUAL(part.stuck[part_row], trace.stuck[row]);
}

}  // namespace

TEST_GROUP(SimulationTrace){};

// A run made in parts (a recording split at its gaps) reuses one trace: emptied, then each part
// appended. Nothing of the previous run may remain and every part's rows follow in order.
TEST(SimulationTrace, AnEmptiedTraceHoldsTheAppendedPartsRowsInOrderAndNothingElse) {
  const SimulationTrace<double> first = numbered_trace(3, 10.0);
  const SimulationTrace<double> second = numbered_trace(4, 20.0);
  SimulationTrace<double> run = numbered_trace(9, 90.0);  // the previous, longer run
  run.resize(0);
  run.append(first);
  run.append(second);
  const std::size_t rows = first.x_r_m.size() + second.x_r_m.size();
  for (const std::size_t size : {run.x_r_m.size(), run.v_r_m_per_s.size(), run.a_x_m_per_s2.size(),
                                 run.friction_n.size(), run.stuck.size()})
    UNSIGNED_LONGS_EQUAL(rows, size);
  for (std::size_t row = 0; row < first.x_r_m.size(); ++row) check_row(run, row, first, row);
  for (std::size_t row = 0; row < second.x_r_m.size(); ++row)
    check_row(run, first.x_r_m.size() + row, second, row);
}
