// configure() with arbitrary parameter bytes, then a few thousand steps: for an accepted
// configuration no output may be NaN/Inf and the non-finite guard may never have to restart the
// state (finite input; the input may also hold NaN/Inf samples, which the step must replace).
// Every model x smoothing law x integrator, float and double.
//
// Layout: byte 0 picks the model, law, integrator and scalar type; then per parameter a selector
// byte (raw IEEE bits, or a physical magnitude 10^[-9, 10] with a sign, or 0) and 8 bytes; then
// the input: amplitude, frequency and seed of a deterministic signal, and the step count.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "stickslip/models/dispatch.hpp"

namespace {

using namespace stickslip;

// The case being run, printed when a check fails (so a crash artifact explains itself).
char current_case[512];

void check(bool condition) {
  if (condition) return;
  std::fprintf(stderr, "fuzz_configure_step: check failed for %s\n", current_case);
  __builtin_trap();
}

double parameter(FuzzedDataProvider& in, double typical) {
  const std::uint8_t selector = in.ConsumeIntegral<std::uint8_t>();
  const std::uint64_t bits = in.ConsumeIntegral<std::uint64_t>();
  switch (selector % 8) {
    case 0: {  // raw bits: NaN, Inf, subnormals, anything
      double value = 0.0;
      std::memcpy(&value, &bits, sizeof value);
      return value;
    }
    case 1:
      return 0.0;
    case 2:
      return typical;
    default: {  // +-10^[-9, 10], a few bits of mantissa
      const double exponent = -9.0 + 19.0 * static_cast<double>(bits & 0xFFFFF) / 1048575.0;
      const double value = std::pow(10.0, exponent);
      return (selector & 0x80) != 0 && (selector & 0x40) != 0 ? -value : value;
    }
  }
}

template <typename T>
bool finite_output(const StepOutput<T>& out) {
  return std::isfinite(out.x_r_m) && std::isfinite(out.v_r_m_per_s) &&
         std::isfinite(out.a_x_m_per_s2) && std::isfinite(out.friction_n) &&
         std::isfinite(out.stuck_time_s) && std::isfinite(out.stuck_fraction);
}

template <typename T>
void run(const OscillatorParams& p, double amplitude, double frequency_hz, std::uint64_t seed,
         int steps, bool inject_non_finite) {
  with_oscillator<T>(p, [&](auto& seat) {
    if (!seat.configure(p).ok()) return 0;
    seat.reset(T(0), T(0), T(0));
    check(finite_output(seat.current()));
    std::uint64_t state = seed;
    const double phase_step = 2.0 * 3.14159265358979323846 * frequency_hz * p.dt_s;
    for (int n = 1; n <= steps; ++n) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;  // LCG noise
      const double noise = static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0) - 0.5;
      // The phase from the integer index (no accumulated time), reduced to one period.
      const double phase = std::fmod(phase_step * static_cast<double>(n), 6.283185307179586);
      double a = amplitude * (std::sin(phase) + noise);
      if (inject_non_finite && (state >> 60) == 0)
        a = (state & 1) != 0 ? std::numeric_limits<double>::quiet_NaN()
                             : -std::numeric_limits<double>::infinity();
      const auto out = seat.step(static_cast<T>(a));
      check(finite_output(out));
    }
    check(seat.state_resets() == 0);
    return 0;
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const std::uint8_t choice = in.ConsumeIntegral<std::uint8_t>();
  OscillatorParams p;
  p.model = static_cast<FrictionModel>(choice % 5);
  p.smoothing = static_cast<SmoothingLaw>((choice / 5) % 4);
  p.integrator = static_cast<Integrator>((choice / 20) % 4);
  const bool in_float = (choice / 80) % 2 != 0;
  p.mass_kg = parameter(in, 88.4);
  p.stiffness_n_per_m = parameter(in, 11500.0);
  p.damping_ns_per_m = parameter(in, 504.0);
  p.kinetic_friction_n = parameter(in, 40.0);
  p.static_friction_n = parameter(in, 50.0);
  p.stribeck_velocity_m_per_s = parameter(in, 0.01);
  p.smoothing_constant_s_per_m = parameter(in, 1000.0);
  p.dt_s = parameter(in, 1e-3);
  const double amplitude = std::pow(10.0, in.ConsumeFloatingPointInRange(-3.0, 3.0));
  const double frequency_hz = in.ConsumeFloatingPointInRange(0.0, 50.0);
  const std::uint64_t seed = in.ConsumeIntegral<std::uint64_t>();
  const int steps = in.ConsumeIntegralInRange(1, 3000);
  const bool inject = in.ConsumeBool();
  std::snprintf(current_case, sizeof current_case,
                "%s %s/%s %s m=%.17g k=%.17g b=%.17g F_fk=%.17g F_fs=%.17g v_S=%.17g c=%.17g "
                "dt=%.17g amplitude=%.17g f=%.17g seed=%llu steps=%d inject=%d",
                in_float ? "float" : "double", model_name(p.model), smoothing_name(p.smoothing),
                integrator_name(p.integrator), p.mass_kg, p.stiffness_n_per_m, p.damping_ns_per_m,
                p.kinetic_friction_n, p.static_friction_n, p.stribeck_velocity_m_per_s,
                p.smoothing_constant_s_per_m, p.dt_s, amplitude, frequency_hz,
                static_cast<unsigned long long>(seed), steps, inject ? 1 : 0);
  if (in_float) {
    run<float>(p, amplitude, frequency_hz, seed, steps, inject);
  } else {
    run<double>(p, amplitude, frequency_hz, seed, steps, inject);
  }
  return 0;
}
