// Property: `simulate` and `replay` agree bit for bit, and two runs of each are identical, over
// hundreds of random scenes (fixed seed). Each case runs the functions the command line runs
// (simulate_file() and replay_file(), stickslip/host/{run/simulate_file,bus/bus_commands}.hpp)
// in this process: replay encodes the recording as SeatInput frames, sends them over the
// in-process loopback bus to an ECU node (receive checker, decode, the Observer's model step) and
// writes the node's rows; simulate runs the same scene on the quantised samples (a_u through
// quantise and decode, the codec's contract), as docs/CAN.md and tests/can/test_replay.cpp
// describe. The outputs are compared byte for byte: every number is written with 17 significant
// digits (format_g17), which tells any two different doubles apart, so equal files mean equal
// bits in every column of every row (-0 and 0 included); the run figures of the summaries are
// compared with memcmp.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "property/property_support.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/simulate_file.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

// 120 per scalar type (double, float, fixed). Under AddressSanitizer (tools/sanitize.sh, where a
// case costs six times as much) a third of them, the first 120: they take every path of both
// commands the full set takes, and the release suite runs all 360.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kCases = 120;
#else
constexpr int kCases = 360;
#endif

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// t = n dt from the integer n (no accumulated time); a_u as given or quantised.
void write_signal(const std::string& path, double dt_s, const std::vector<double>& a_u,
                  bool quantised) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  CHECK(file != nullptr);
  std::fprintf(file, "t,a_u\n");
  for (std::size_t n = 0; n < a_u.size(); ++n)
    std::fprintf(file, "%.17g,%.17g\n", static_cast<double>(n) * dt_s,
                 quantised ? can::quantised_input(a_u[n]) : a_u[n]);
  std::fclose(file);
}

template <typename T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// The summary's run figures, which both paths compute from the same statistics of the same
// samples (ride comfort and the observer's window are the node's own, not simulate's).
bool same_run_figures(const host::SimulationSummary& a, const host::SimulationSummary& b) {
  return a.samples == b.samples && a.steps == b.steps && same_bits(a.dt_s, b.dt_s) &&
         same_bits(a.rms_u, b.rms_u) && same_bits(a.rms_x, b.rms_x) &&
         same_bits(a.transmissibility, b.transmissibility) &&
         same_bits(a.stick_probability, b.stick_probability) &&
         same_bits(a.den_hartog_k, b.den_hartog_k) && a.events == b.events &&
         a.rejected_inputs == b.rejected_inputs &&
         a.event_budget_exhausted == b.event_budget_exhausted && a.state_resets == b.state_resets &&
         a.saturated_steps == b.saturated_steps;
}

struct Case {
  host::SimulationSetup setup;
  host::ScalarType scalar = host::ScalarType::float64;
  std::vector<double> a_u;
};

// Random model parameters over the ranges configure() accepts (property_support.hpp), a model
// the scalar type offers, an integrator (half the cases exact, the default of every law), a
// short lorry-like input of 64..400 samples, in a tenth of the cases one sample beyond the CAN
// range (+-32 m/s^2: saturated by the encoder), and in a quarter a non-zero initial state.
Case random_case(test::SplitMix64& random, int trial) {
  Case c;
  c.scalar = static_cast<host::ScalarType>(trial % 3);
  static constexpr FrictionModel kFixedModels[] = {FrictionModel::linear, FrictionModel::signum,
                                                   FrictionModel::smooth,
                                                   FrictionModel::stick_slip};
  const FrictionModel model = c.scalar == host::ScalarType::fixed
                                  ? kFixedModels[random.next() % 4]
                                  : test::kAllModels[random.next() % 5];
  const Integrator integrator =
      random.uniform(0.0, 1.0) < 0.5 ? Integrator::exact : test::kAllIntegrators[random.next() % 4];
  c.setup.params = test::random_params(random, model, integrator);
  if (c.scalar == host::ScalarType::fixed) c.setup.params.smoothing = SmoothingLaw::rational;
  c.setup.repetitions = 1;
  if (random.uniform(0.0, 1.0) < 0.25) {
    c.setup.x0_m = random.uniform(-0.05, 0.05);
    c.setup.v0_m_per_s = random.uniform(-0.3, 0.3);
  }
  const std::size_t steps = 63 + random.next() % 338;
  c.a_u = test::random_input(random, c.setup.params.dt_s, steps);
  if (random.uniform(0.0, 1.0) < 0.1)
    c.a_u[1 + random.next() % steps] = random.uniform(0.0, 1.0) < 0.5 ? 40.0 : -40.0;
  return c;
}

SimpleString describe(const Case& c, int trial) {
  const OscillatorParams& p = c.setup.params;
  return StringFromFormat(
      "case %d: %s %s/%s %s m=%.6g k=%.6g b=%.6g F_fk=%.6g F_fs=%.6g v_S=%.3g "
      "c=%.6g dt=%.6g x0=%.3g v0=%.3g, %zu samples",
      trial, host::scalar_name(c.scalar), model_name(p.model), smoothing_name(p.smoothing),
      integrator_name(p.integrator), p.mass_kg, p.stiffness_n_per_m, p.damping_ns_per_m,
      p.kinetic_friction_n, p.static_friction_n, p.stribeck_velocity_m_per_s,
      p.smoothing_constant_s_per_m, p.dt_s, c.setup.x0_m, c.setup.v0_m_per_s, c.a_u.size());
}

struct Outcome {
  bool refused = false;
  std::string text;  // the output CSV
  host::SimulationSummary summary;
};

Outcome simulate(const Case& c, const std::string& input, const std::string& output) {
  host::SimulateRequest request;
  request.input_path = input;
  request.output_path = output;
  request.setup = c.setup;
  request.scalar = c.scalar;
  Outcome outcome;
  try {
    outcome.summary = host::simulate_file(request).summary;
  } catch (const host::HostError&) {  // configure() refused the scene: no output written
    outcome.refused = true;
    return outcome;
  }
  outcome.text = read_text(output);
  std::filesystem::remove(output);
  return outcome;
}

Outcome replay(const Case& c, const std::string& input, const std::string& output,
               std::uint64_t& saturated) {
  host::ReplayRequest request;
  request.input_path = input;
  request.output_path = output;
  request.bus = "loopback";
  request.setup = c.setup;
  request.scalar = c.scalar;
  Outcome outcome;
  try {
    const host::ReplayResult result = host::replay_file(request);
    outcome.summary = result.summary;
    saturated = result.input_saturated;
    CHECK_EQUAL(0u, result.faults.faults());
    CHECK_EQUAL(c.a_u.size(), result.faults.accepted);
  } catch (const host::HostError&) {  // the node's configure() refused the scene
    outcome.refused = true;
    return outcome;
  }
  outcome.text = read_text(output);
  std::filesystem::remove(output);
  return outcome;
}

}  // namespace

TEST_GROUP(SimulateReplayProperty) {
  std::string dir;
  void setup() override {
    dir = (std::filesystem::temp_directory_path() /
           ("stickslip-prop-" + std::to_string(static_cast<long>(::getpid()))))
              .string();
    std::filesystem::create_directories(dir);
  }
  void teardown() override {
    std::filesystem::remove_all(dir);
  }
};

TEST(SimulateReplayProperty, SimulateEqualsReplayBitForBitAndRunsRepeat) {
  test::SplitMix64 random(0x5eed0007);
  const std::string raw = dir + "/raw.csv", quantised = dir + "/quantised.csv";
  const std::string out = dir + "/out.csv";
  int compared[3] = {0, 0, 0}, refused = 0, saturated_cases = 0;
  std::size_t rows = 0;
  for (int trial = 0; trial < kCases; ++trial) {
    const Case c = random_case(random, trial);
    write_signal(raw, c.setup.params.dt_s, c.a_u, false);
    write_signal(quantised, c.setup.params.dt_s, c.a_u, true);
    const SimpleString what = describe(c, trial);
    std::uint64_t saturated = 0, saturated_again = 0;
    const Outcome s1 = simulate(c, quantised, out), s2 = simulate(c, quantised, out);
    const Outcome r1 = replay(c, raw, out, saturated), r2 = replay(c, raw, out, saturated_again);
    // Both paths refuse the same scenes (the same configure()), and refuse them every time.
    CHECK_TEXT(s1.refused == r1.refused && s1.refused == s2.refused && r1.refused == r2.refused,
               what.asCharString());
    if (s1.refused) {
      ++refused;
      continue;
    }
    CHECK_TEXT(s1.text == s2.text && same_run_figures(s1.summary, s2.summary),
               (SimpleString("two simulate runs differ: ") + what).asCharString());
    CHECK_TEXT(r1.text == r2.text && same_run_figures(r1.summary, r2.summary) &&
                   saturated == saturated_again,
               (SimpleString("two replay runs differ: ") + what).asCharString());
    CHECK_TEXT(s1.text == r1.text,
               (SimpleString("simulate != replay (rows): ") + what).asCharString());
    CHECK_TEXT(same_run_figures(s1.summary, r1.summary),
               (SimpleString("simulate != replay (figures): ") + what).asCharString());
    CHECK_EQUAL(c.a_u.size(), s1.summary.samples);
    saturated_cases += saturated > 0 ? 1 : 0;
    rows += c.a_u.size();
    ++compared[static_cast<int>(c.scalar)];
  }
  // Hundreds compared, each scalar type well represented; the saturation path was exercised.
  CHECK(compared[0] + compared[1] + compared[2] >= kCases * 5 / 6);
  for (int count : compared) CHECK(count >= kCases * 2 / 9);
  CHECK(saturated_cases >= kCases / 36);
  test::note_margin("simulate == replay: double cases compared", compared[0], kCases / 3);
  test::note_margin("simulate == replay: float cases compared", compared[1], kCases / 3);
  test::note_margin("simulate == replay: fixed-point cases compared", compared[2], kCases / 3);
  test::note_margin("simulate == replay: cases with a saturated input sample", saturated_cases,
                    0.0);
  test::note_margin("simulate == replay: refused by configure() on both paths", refused, 0.0);
  test::note_margin("simulate == replay: rows compared", static_cast<double>(rows), 0.0);
}
