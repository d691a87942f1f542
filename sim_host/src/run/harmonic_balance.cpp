#include "stickslip/host/run/harmonic_balance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/signals/deterministic_math.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"

namespace stickslip::host {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

HarmonicBalance den_hartog_harmonic_balance(const OscillatorParams& params,
                                            double amplitude_m_per_s2, double frequency_hz) {
  const double m = params.mass_kg, k = params.stiffness_n_per_m, b = params.damping_ns_per_m;
  const double w = 2.0 * kPi * frequency_hz;
  const double force = m * amplitude_m_per_s2;             // m A
  const double f = 4.0 * params.kinetic_friction_n / kPi;  // first harmonic of the friction
  HarmonicBalance out;
  out.k = f / force;
  if (!(f < force)) return out;  // K >= 1: no non-stop solution
  out.valid = true;
  const double spring = k - m * w * w;
  const double viscous = b * w;
  const double d = spring * spring + viscous * viscous;
  if (d == 0.0) {
    out.amplitude_m = std::numeric_limits<double>::infinity();
    out.phase_rad = 0.5 * kPi;
    return out;
  }
  // Written so that f = 0 gives m A / sqrt(D) (the root of the linear case) exactly:
  // X = (sqrt((b w f)^2 + D (mA^2 - f^2)) - b w f) / D.
  const double bwf = viscous * f;
  out.amplitude_m = (std::sqrt(bwf * bwf + d * (force * force - f * f)) - bwf) / d;
  out.phase_rad = std::atan2(viscous * out.amplitude_m + f, spring * out.amplitude_m);
  return out;
}

SteadyState simulate_harmonic_steady_state(const OscillatorParams& params,
                                           double amplitude_m_per_s2, double frequency_hz,
                                           double periods) {
  const double dt = params.dt_s;
  const auto steps = static_cast<std::size_t>(std::llround(periods / frequency_hz / dt));
  const std::size_t measure_from = steps - steps / 4;
  const double w = 2.0 * kPi * frequency_hz;
  // Linear steady state of x'' + (b/m) x' + (k/m) x = -A sin(w t): x = Im(X e^{iwt}).
  const std::complex<double> x_hat =
      -amplitude_m_per_s2 / std::complex<double>(params.stiffness_n_per_m / params.mass_kg - w * w,
                                                 w * params.damping_ns_per_m / params.mass_kg);
  const double x0 = x_hat.imag(), v0 = w * x_hat.real();
  const auto input = [&](std::size_t n) {
    return amplitude_m_per_s2 *
           deterministic_sincos_cycles(frequency_hz * static_cast<double>(n) * dt).sin;
  };
  return with_oscillator<double>(params, [&](auto& oscillator) {
    const ConfigResult configured = oscillator.configure(params);
    if (!configured.ok()) throw HostError(configured.message.c_str());
    oscillator.reset(x0, v0, input(0));
    RunningStatistics<double> statistics;
    statistics.reset();
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (std::size_t n = 1; n <= steps; ++n) {
      const double a_u = input(n);
      const StepOutput<double> out = oscillator.step(a_u);
      if (n >= measure_from) {
        low = std::min(low, out.x_r_m);
        high = std::max(high, out.x_r_m);
        statistics.add_sample(a_u, out.a_x_m_per_s2);
        statistics.add_step(out.stuck_fraction);
      }
    }
    SteadyState s;
    s.amplitude_m = 0.5 * (high - low);
    s.stick_probability = statistics.stick_probability();
    s.transmissibility = statistics.transmissibility();
    return s;
  });
}

std::size_t write_harmonic_balance_sweep(const HarmonicBalanceSweepRequest& r,
                                         const std::string& path) {
  double low = 0.0, high = 0.0;
  int count = 0;
  char tail = 0;
  if (std::sscanf(r.k_range.c_str(), "%lf:%lf:%d%c", &low, &high, &count, &tail) != 3 ||
      count < 2 || !(high > low) || low < 0.0) {
    throw UsageError("--k-range: expected MIN:MAX:COUNT with 0 <= MIN < MAX, COUNT >= 2, got '" +
                     r.k_range + "'");
  }
  if (!(r.frequency_hz > 0.0) || !(r.amplitude_m_per_s2 > 0.0) || !(r.periods >= 4.0) ||
      !(r.dt_s > 0.0) || !(r.frequency_hz < 0.1 / r.dt_s)) {
    throw UsageError(
        "--frequency/--amplitude/--periods/--dt: need f > 0, A > 0, periods >= 4, "
        "0 < dt < 0.1/f");
  }
  AtomicOutputFile file(path);
  CsvWriter writer(file);
  writer.text("b_ns_per_m,K,ffk_n,hb_valid,x_hb_m,x_sim_m,x_linear_m,p_sim,T_ax_sim,rel_error\n");
  std::size_t rows = 0;
  for (double b : r.damping_ns_per_m) {
    for (int i = 0; i < count; ++i) {
      const double k_value = low + (high - low) * i / (count - 1);
      OscillatorParams p;
      p.mass_kg = r.mass_kg;
      p.stiffness_n_per_m = r.stiffness_n_per_m;
      p.damping_ns_per_m = b;
      // K = 4 F / (pi m A)
      p.kinetic_friction_n = p.static_friction_n =
          k_value * kPi * r.mass_kg * r.amplitude_m_per_s2 / 4.0;
      p.model = FrictionModel::stick_slip;
      p.integrator = Integrator::exact;
      p.dt_s = r.dt_s;
      const HarmonicBalance hb =
          den_hartog_harmonic_balance(p, r.amplitude_m_per_s2, r.frequency_hz);
      OscillatorParams linear = p;
      linear.kinetic_friction_n = linear.static_friction_n = 0.0;
      const double x_linear =
          den_hartog_harmonic_balance(linear, r.amplitude_m_per_s2, r.frequency_hz).amplitude_m;
      const SteadyState sim =
          simulate_harmonic_steady_state(p, r.amplitude_m_per_s2, r.frequency_hz, r.periods);
      for (double value : {b, k_value, p.kinetic_friction_n}) {
        writer.number(value);
        writer.separator();
      }
      writer.flag(hb.valid);
      // Without a harmonic-balance solution there is nothing to compare: "nan", which no
      // reader can take for a perfect match as it would a 0.
      const double none = std::numeric_limits<double>::quiet_NaN();
      for (double value :
           {hb.valid ? hb.amplitude_m : none, sim.amplitude_m, x_linear, sim.stick_probability,
            sim.transmissibility,
            hb.valid && sim.amplitude_m > 0.0 ? hb.amplitude_m / sim.amplitude_m - 1.0 : none}) {
        writer.separator();
        if (std::isnan(value)) {
          writer.text("nan");
        } else {
          writer.number(value);
        }
      }
      writer.end_row();
      ++rows;
    }
  }
  writer.flush();
  file.commit();
  return rows;
}

}  // namespace stickslip::host
