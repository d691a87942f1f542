// configure()'s work: validation and every coefficient of the step, in long double.
#include "stickslip/integrators/discretisation.hpp"

#include <cmath>

#include "stickslip/integrators/taylor_segment.hpp"

namespace stickslip {
namespace {

using Real = long double;
constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxMagnitude =
    1e9;  // bound on forces, masses, stiffnesses: keeps products finite
// Lower bounds that keep every coefficient a finite, normal number in float as well (k/m, 1/dt,
// 1/v_S, the maps of dt/2^16): a denormal dt or v_S would reach the float step as 0 or infinity.
constexpr double kMinMagnitude = 1e-6;  // mass_kg, stiffness_n_per_m
constexpr double kMinStep = 1e-9;       // dt_s, stribeck_velocity_m_per_s, smoothing constant
constexpr double kStabilityTolerance =
    1e-12;  // spectral radius 1 + rounding still counts as stable
// Semi-implicit Euler restarted at in-step reversals drifts energy by about 1.35 (omega0 dt)^2 per
// cycle (measured: a staggered velocity does not survive the restart); viscous damping removes
// 4 pi zeta per cycle. Sticking laws with symplectic need zeta >= this factor * (omega0 dt)^2,
// twice the measured balance.
constexpr double kSymplecticEventDampingFactor = 0.25;
// The in-step event search assumes at most one extremum of v_r per step in each mode.
constexpr double kMaxEventPhase = kPi / 2.0;  // omega0 * dt

// Explicit widening (clang's -Wdouble-promotion asks for it; the promotion is wanted here).
constexpr Real wide(double value) {
  return static_cast<Real>(value);
}

struct Mat4 {
  Real a[4][4];
};

Mat4 multiply(const Mat4& left, const Mat4& right) {
  Mat4 out{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      Real sum = 0;
      for (int k = 0; k < 4; ++k) sum += left.a[i][k] * right.a[k][j];
      out.a[i][j] = sum;
    }
  return out;
}

// exp(M) by scaling and squaring with a degree-24 Taylor polynomial: robust for under-, critically
// and over-damped systems and b = 0 alike, with no case distinctions. With `minus_identity`,
// exp(M) - I, its entries each to the relative precision of a Real: the series without its
// first term, and each squaring as (I + D)^2 - I = 2 D + D^2, so that the diagonal near 1 never
// holds the 1.
Mat4 exponential(Mat4 m, bool minus_identity = false) {
  Real norm = 0;
  for (int j = 0; j < 4; ++j) {
    Real column = 0;
    for (int i = 0; i < 4; ++i) column += std::fabs(m.a[i][j]);
    if (column > norm) norm = column;
  }
  int squarings = 0;
  while (norm > 0.125L && squarings < 200) {
    norm *= 0.5L;
    ++squarings;
  }
  const Real scale = std::ldexp(Real(1), -squarings);
  for (auto& row : m.a)
    for (Real& value : row) value *= scale;
  Mat4 result{}, term{};
  for (int i = 0; i < 4; ++i) term.a[i][i] = 1;
  if (!minus_identity)
    for (int i = 0; i < 4; ++i) result.a[i][i] = 1;
  for (int k = 1; k <= 24; ++k) {
    term = multiply(term, m);
    for (auto& row : term.a)
      for (Real& value : row) value /= static_cast<Real>(k);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) result.a[i][j] += term.a[i][j];
  }
  for (int s = 0; s < squarings; ++s) {
    Mat4 square = multiply(result, result);
    if (minus_identity)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) square.a[i][j] += 2 * result.a[i][j];
    result = square;
  }
  return result;
}

// Exact discretisation with first-order hold: augment the state with g and its slope w,
// z = [x, v, g, w], z' = M z, so exp(M h) carries the input's response along.
//
// The state is balanced first: v divided by c, g and w by c^2, c the power of two nearest
// omega0 = sqrt(k/m) (exact scalings). The rotation block is then about [[0, omega0 h],
// [-omega0 h, -b h/m]] instead of [[0, h], [-omega0^2 h, -b h/m]], whose norm, omega0^2 h, would
// set the number of squarings where the motion turns by omega0 h. On stiff stops (omega0 dt =
// pi/2 at 1 ms, omega0^2 dt = 2.5e3) that was 15 squarings instead of 5, each doubling the
// relative error: coefficients 1.7e-15 off, the whole step's determinant 2.9e-15 from
// exp(-b dt/m), and an undamped seat's energy drifting by that much with every step. Of 84
// seats compared (88.4 kg, k from 3.2e3 to 1e8 N/m, b up to 2,504 N s/m, dt 0.1 to 2 ms) only
// those of 1e7 N/m and more got other doubles: the reference seat, and it on stops of up to
// 1e6 N/m, keep every coefficient.
struct BalancedExponential {
  Mat4 e;  // exp(m) or exp(m) - I, with m the balanced matrix
  Real c;  // the balance: E = D e D^-1 (+ I), D = diag(1, c, c^2, c^2)
};

BalancedExponential balanced_exponential(Real k_m, Real b_m, Real h, bool minus_identity) {
  const int scale_exponent = k_m > 0 ? static_cast<int>(std::lround(0.5L * std::log2(k_m))) : 0;
  const Real c = std::ldexp(Real(1), scale_exponent);
  Mat4 m{};
  m.a[0][1] = h * c;
  m.a[1][0] = -k_m * h / c;
  m.a[1][1] = -b_m * h;
  m.a[1][2] = h * c;
  m.a[2][3] = 1;  // in step-normalised time s = t/h the input rises by q = g1 - g0 per step
  return {exponential(m, minus_identity), c};
}

// The map's coefficients from the balanced exponential (E, or E - I), z(1) = E z(0) with
// z(0) = [x, v, g0, g1 - g0].
StepMap<double> unbalanced_map(const BalancedExponential& b) {
  const Mat4& e = b.e;
  const Real c = b.c, c2 = c * c;
  StepMap<double> out{};
  out.xx = static_cast<double>(e.a[0][0]);
  out.xv = static_cast<double>(e.a[0][1] / c);
  out.vx = static_cast<double>(e.a[1][0] * c);
  out.vv = static_cast<double>(e.a[1][1]);
  out.gx0 = static_cast<double>((e.a[0][2] - e.a[0][3]) / c2);
  out.gx1 = static_cast<double>(e.a[0][3] / c2);
  out.gv0 = static_cast<double>((e.a[1][2] - e.a[1][3]) / c);
  out.gv1 = static_cast<double>(e.a[1][3] / c);
  return out;
}

StepMap<double> exact_map(Real k_m, Real b_m, Real h) {
  return unbalanced_map(balanced_exponential(k_m, b_m, h, false));
}

// RK4 on the affine system, applied to the basis vectors (the map is linear in x, v, g0, g1).
void rk4_apply(Real k_m, Real b_m, Real h, Real x, Real v, Real g0, Real g1, Real& x_out,
               Real& v_out) {
  const Real g_mid = (g0 + g1) / 2;
  auto acc = [&](Real xs, Real vs, Real g) { return -k_m * xs - b_m * vs + g; };
  const Real k1x = v, k1v = acc(x, v, g0);
  const Real k2x = v + h / 2 * k1v, k2v = acc(x + h / 2 * k1x, v + h / 2 * k1v, g_mid);
  const Real k3x = v + h / 2 * k2v, k3v = acc(x + h / 2 * k2x, v + h / 2 * k2v, g_mid);
  const Real k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v, g1);
  x_out = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
  v_out = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

StepMap<double> rk4_map(Real k_m, Real b_m, Real h) {
  Real columns[4][2];
  const Real basis[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  for (int c = 0; c < 4; ++c)
    rk4_apply(k_m, b_m, h, basis[c][0], basis[c][1], basis[c][2], basis[c][3], columns[c][0],
              columns[c][1]);
  StepMap<double> out{};
  out.xx = static_cast<double>(columns[0][0]);
  out.vx = static_cast<double>(columns[0][1]);
  out.xv = static_cast<double>(columns[1][0]);
  out.vv = static_cast<double>(columns[1][1]);
  out.gx0 = static_cast<double>(columns[2][0]);
  out.gv0 = static_cast<double>(columns[2][1]);
  out.gx1 = static_cast<double>(columns[3][0]);
  out.gv1 = static_cast<double>(columns[3][1]);
  return out;
}

StepMap<double> map_for(Integrator integrator, Real k_m, Real b_m, Real h) {
  StepMap<double> out{};
  switch (integrator) {
    case Integrator::euler:  // ode1: state, friction and input all from the start of the step
      out.xx = 1.0;
      out.xv = static_cast<double>(h);
      out.vx = static_cast<double>(-h * k_m);
      out.vv = static_cast<double>(1 - h * b_m);
      out.gv0 = static_cast<double>(h);
      return out;
    case Integrator::symplectic:  // v first, then x with the updated v
      out.xx = static_cast<double>(1 - h * h * k_m);
      out.xv = static_cast<double>(h * (1 - h * b_m));
      out.vx = static_cast<double>(-h * k_m);
      out.vv = static_cast<double>(1 - h * b_m);
      out.gx0 = static_cast<double>(h * h);
      out.gv0 = static_cast<double>(h);
      return out;
    case Integrator::rk4:
      return rk4_map(k_m, b_m, h);
    case Integrator::exact:
      break;
  }
  return exact_map(k_m, b_m, h);
}

// d F_f / d v_r at v_r = 0 for the smoothed forms, N s/m: the friction acts as a damper there,
// which is what limits explicit integrators.
double smoothing_slope(const OscillatorParams& p) {
  const double c = p.smoothing_constant_s_per_m, f = p.kinetic_friction_n;
  switch (p.smoothing) {
    case SmoothingLaw::atan:
      return f * c * 2.0 / kPi;
    case SmoothingLaw::erf:
      return f * c * 2.0 / std::sqrt(kPi);
    case SmoothingLaw::tanh:
    case SmoothingLaw::rational:
      break;
  }
  return f * c;
}

// Spectral radius of the one-step map linearised at v_r = 0 for step h; `slope` is dF_f/dv_r.
double linearised_radius(const OscillatorParams& p, double h, double slope) {
  const Real k_m = wide(p.stiffness_n_per_m) / wide(p.mass_kg);
  const Real b_m = wide(p.damping_ns_per_m) / wide(p.mass_kg);
  const Real s_m = wide(slope) / wide(p.mass_kg);
  if (slope > 0.0 && p.integrator == Integrator::rk4) {
    return spectral_radius(
        map_for(p.integrator, k_m, b_m + s_m, wide(h)));  // friction at every stage
  }
  StepMap<double> m = map_for(p.integrator, k_m, b_m, wide(h));
  if (slope > 0.0) {  // friction held from the start of the step enters through g0 and g1
    const double s = static_cast<double>(s_m);
    m.xv -= s * (m.gx0 + m.gx1);
    m.vv -= s * (m.gv0 + m.gv1);
  }
  return spectral_radius(m);
}

// Stable both near v_r = 0 (friction acting as a damper of `slope`) and with the friction
// saturated (the linear part alone).
bool stable(const OscillatorParams& p, double h, double slope) {
  const double limit = 1.0 + kStabilityTolerance;
  if (!(linearised_radius(p, h, 0.0) <= limit)) return false;
  return slope <= 0.0 || linearised_radius(p, h, slope) <= limit;
}

ConfigResult fail(Status status, const char* parameter) {
  ConfigResult r = refusal(status);
  r.message.append(parameter).append(": ");
  return r;
}

bool check_finite(const OscillatorParams& p, ConfigResult& r) {
  struct Named {
    const char* name;
    double value;
  };
  const Named all[] = {{"mass_kg", p.mass_kg},
                       {"stiffness_n_per_m", p.stiffness_n_per_m},
                       {"damping_ns_per_m", p.damping_ns_per_m},
                       {"kinetic_friction_n", p.kinetic_friction_n},
                       {"static_friction_n", p.static_friction_n},
                       {"stribeck_velocity_m_per_s", p.stribeck_velocity_m_per_s},
                       {"smoothing_constant_s_per_m", p.smoothing_constant_s_per_m},
                       {"dt_s", p.dt_s}};
  for (const Named& n : all) {
    if (!std::isfinite(n.value)) {
      r = fail(Status::not_finite, n.name);
      r.message.append("must be a finite number, got ").append(n.value);
      return false;
    }
  }
  return true;
}

// lower < value <= upper (or lower <= value with `inclusive_lower`).
bool check_range(const char* name, double value, double lower, bool inclusive_lower, double upper,
                 const char* unit, ConfigResult& r) {
  const bool low_ok = inclusive_lower ? value >= lower : value > lower;
  if (low_ok && value <= upper) return true;
  r = fail(Status::out_of_range, name);
  r.message.append("must be ")
      .append(inclusive_lower ? ">= " : "> ")
      .append(lower)
      .append(" and <= ")
      .append(upper)
      .append(" ")
      .append(unit)
      .append(", got ")
      .append(value);
  return false;
}

// Largest h in (0, dt] for which the linearised map is stable (0 if none), by bisection.
double stable_step_limit(const OscillatorParams& p, double slope) {
  double bad = p.dt_s, good = 0.0;
  double trial = p.dt_s;
  for (int i = 0; i < 80; ++i) {  // find some stable step by halving
    trial *= 0.5;
    if (stable(p, trial, slope)) {
      good = trial;
      break;
    }
    bad = trial;
  }
  if (good == 0.0) return 0.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (good + bad);
    (stable(p, mid, slope) ? good : bad) = mid;
  }
  return good;
}

// The parameters alone: finite, within their physical ranges, F_fs >= F_fk.
bool check_parameters(const OscillatorParams& p, ConfigResult& r) {
  if (!check_finite(p, r)) return false;
  if (!check_range("mass_kg", p.mass_kg, kMinMagnitude, true, kMaxMagnitude, "kg", r)) return false;
  if (!check_range("stiffness_n_per_m", p.stiffness_n_per_m, kMinMagnitude, true, kMaxMagnitude,
                   "N/m", r))
    return false;
  if (!check_range("damping_ns_per_m", p.damping_ns_per_m, 0.0, true, kMaxMagnitude, "N s/m", r))
    return false;
  if (!check_range("dt_s", p.dt_s, kMinStep, true, 1.0, "s", r)) return false;
  const bool has_friction = p.model != FrictionModel::linear;
  const bool sticking = p.model == FrictionModel::stick_slip || p.model == FrictionModel::stribeck;
  if (has_friction &&
      !check_range("kinetic_friction_n", p.kinetic_friction_n, 0.0, true, kMaxMagnitude, "N", r))
    return false;
  if (sticking) {
    if (!check_range("static_friction_n", p.static_friction_n, 0.0, true, kMaxMagnitude, "N", r))
      return false;
    if (p.static_friction_n < p.kinetic_friction_n) {
      r = fail(Status::static_below_kinetic, "static_friction_n");
      r.message.append("F_fs = ")
          .append(p.static_friction_n)
          .append(" N is below the kinetic friction F_fk = ")
          .append(p.kinetic_friction_n)
          .append(" N; static friction must be >= kinetic");
      return false;
    }
  }
  if (p.model == FrictionModel::stribeck &&
      !check_range("stribeck_velocity_m_per_s", p.stribeck_velocity_m_per_s, kMinStep, true, 1e3,
                   "m/s", r))
    return false;
  if (p.model == FrictionModel::smooth &&
      !check_range("smoothing_constant_s_per_m", p.smoothing_constant_s_per_m, kMinStep, true, 1e12,
                   "s/m", r))
    return false;
  return true;
}

// The in-step event search assumes at most one extremum of v_r per step in each mode.
bool check_event_step(const OscillatorParams& p, double omega0, ConfigResult& r) {
  const bool has_friction = p.model != FrictionModel::linear;
  const bool sticking = p.model == FrictionModel::stick_slip || p.model == FrictionModel::stribeck;
  const bool events = sticking || (has_friction && p.integrator == Integrator::exact);
  if (events && omega0 * p.dt_s > kMaxEventPhase) {
    r = fail(Status::out_of_range, "dt_s");
    r.message.append("the in-step event search needs omega0*dt <= pi/2, i.e. dt <= ")
        .append(kMaxEventPhase / omega0)
        .append(" s for omega0 = ")
        .append(omega0)
        .append(" rad/s; got dt = ")
        .append(p.dt_s)
        .append(" s");
    return false;
  }

  return true;
}

// Explicit Euler and symplectic Euler where they have no stable step for this scene.
bool check_euler_variants(const OscillatorParams& p, double omega0, ConfigResult& r) {
  // Explicit Euler on an undamped spring: radius sqrt(1 + (omega0 dt)^2) > 1 for every dt.
  if (p.integrator == Integrator::euler && p.damping_ns_per_m == 0.0) {
    r = fail(Status::unstable, "damping_ns_per_m");
    r.message.append("explicit Euler has no stable dt for an undamped spring (spectral radius ")
        .append(std::sqrt(1.0 + omega0 * omega0 * p.dt_s * p.dt_s), 15)
        .append(" > 1 at dt = ")
        .append(p.dt_s)
        .append(" s); use symplectic, rk4 or exact, or damping > 0");
    return false;
  }
  const bool sticking = p.model == FrictionModel::stick_slip || p.model == FrictionModel::stribeck;
  if (sticking && p.integrator == Integrator::symplectic) {
    const double zeta = p.damping_ns_per_m / (2.0 * std::sqrt(p.stiffness_n_per_m * p.mass_kg));
    const double needed = kSymplecticEventDampingFactor * omega0 * omega0 * p.dt_s * p.dt_s;
    if (zeta < needed && zeta == 0.0) {
      // The limit dt <= sqrt(zeta / 0.25) / omega0 is 0: there is no stable dt to quote.
      r = fail(Status::unstable, "damping_ns_per_m");
      r.message.append("symplectic with ")
          .append(model_name(p.model))
          .append(" events gains energy at reversals; without damping no dt is stable")
          .append(" (stability limit: damping ratio >= 0.25")
          .append(" (omega0 dt)^2 = ")
          .append(needed, 4)
          .append(" at dt = ")
          .append(p.dt_s)
          .append(" s); use damping > 0, or exact/rk4");
      return false;
    }
    if (zeta < needed) {
      r = fail(Status::unstable, "damping_ns_per_m");
      // Kept under StatusMessage's 240 characters, the advice at the end included.
      r.message.append("symplectic with stick-slip events gains about 1.35 (omega0 dt)^2 of energy")
          .append(" per cycle; damping ratio ")
          .append(zeta, 4)
          .append(" is below its stability limit ")
          .append(needed, 4)
          .append(" (0.25 (omega0 dt)^2); use dt <= ")
          .append(std::sqrt(zeta / kSymplecticEventDampingFactor) / omega0, 4)
          .append(" s, more damping, or exact/rk4");
      return false;
    }
  }

  return true;
}

// Stability of the chosen integrator: linearised at v_r = 0 (where a smoothed law is stiffest)
// and with the friction saturated (slope 0, the linear part alone); both must hold. Sets the
// spectral radius found.
bool check_stability(const OscillatorParams& p, double& radius, ConfigResult& r) {
  const bool velocity_friction = p.model == FrictionModel::smooth;
  const bool explicit_friction = velocity_friction && p.integrator != Integrator::exact;
  const double saturated_radius = linearised_radius(p, p.dt_s, 0.0);
  const double slope =
      explicit_friction && saturated_radius <= 1.0 + kStabilityTolerance ? smoothing_slope(p) : 0.0;
  radius = slope > 0.0 ? linearised_radius(p, p.dt_s, slope) : saturated_radius;
  if (!(radius <= 1.0 + kStabilityTolerance)) {
    const double limit = stable_step_limit(p, slope);
    if (slope > 0.0) {
      r = fail(Status::unstable, "smoothing_constant_s_per_m");
      r.message.append("c*F_fk*s'(0)*dt/m = ")
          .append(slope * p.dt_s / p.mass_kg, 4)
          .append(" makes ")
          .append(integrator_name(p.integrator))
          .append(" unstable (spectral radius ")
          .append(radius, 12)
          .append(" > 1); ");
    } else {
      r = fail(Status::unstable, "dt_s");
      r.message.append(integrator_name(p.integrator))
          .append(" is unstable for this spring and damper (spectral radius ")
          .append(radius, 12)
          .append(" > 1); ");
    }
    if (limit > 0.0) {
      r.message.append("the stability limit is dt < ").append(limit, 4).append(" s");
    } else {
      r.message.append("no dt is stable (undamped); use symplectic, rk4 or exact");
    }
    return false;
  }
  return true;
}

// Every coefficient of the step, in long double, rounded once to double.
void fill_model(const OscillatorParams& p, double omega0, double radius, DiscreteModel& out) {
  out.params = p;
  const Real b_m = wide(p.damping_ns_per_m) / wide(p.mass_kg);
  const Real k_m_real = wide(p.stiffness_n_per_m) / wide(p.mass_kg);
  for (int level = 0; level < kMapLevels; ++level) {
    const Real h = std::ldexp(static_cast<Real>(p.dt_s), -level);
    out.maps[level] = map_for(p.integrator, k_m_real, b_m, h);
    out.block_s[level] = static_cast<double>(h);
  }
  out.inv_dt = 1.0 / p.dt_s;
  out.inv_mass = static_cast<double>(1.0L / wide(p.mass_kg));
  out.stiffness_over_mass = static_cast<double>(k_m_real);
  out.damping_over_mass = static_cast<double>(b_m);
  out.stribeck_excess_n = p.static_friction_n - p.kinetic_friction_n;
  out.inv_stribeck_velocity =
      p.stribeck_velocity_m_per_s > 0.0 ? 1.0 / p.stribeck_velocity_m_per_s : 0.0;
  out.smoothing_scale_n =
      p.smoothing == SmoothingLaw::atan ? p.kinetic_friction_n * 2.0 / kPi : p.kinetic_friction_n;
  out.natural_frequency_rad_s = omega0;
  out.spectral_radius = radius;
}

}  // namespace

double spectral_radius(const StepMap<double>& m) noexcept {
  const Real trace = wide(m.xx) + wide(m.vv);
  const Real det = wide(m.xx) * wide(m.vv) - wide(m.xv) * wide(m.vx);
  const Real disc = trace * trace - 4 * det;
  if (disc < 0) return static_cast<double>(std::sqrt(det));
  const Real root = std::sqrt(disc);
  const Real a = std::fabs((trace + root) / 2), b = std::fabs((trace - root) / 2);
  return static_cast<double>(a > b ? a : b);
}

// The exact integrator's from exp(m) - I: E's off-diagonal and input terms, and each diagonal
// term, xx or vv, as itself or less 1, whichever is the smaller; k/m and b/m as
// fill_model() forms them. The other integrators' from their map, where the difference is exact.
NearIdentityStepMap<double> near_identity_step_map(const OscillatorParams& p, int level) noexcept {
  const Real b_m = wide(p.damping_ns_per_m) / wide(p.mass_kg);
  const Real k_m = wide(p.stiffness_n_per_m) / wide(p.mass_kg);
  const Real h = std::ldexp(static_cast<Real>(p.dt_s), -level);
  NearIdentityStepMap<double> out{};
  Real xx = 0, vv = 0;  // the diagonal less 1
  if (p.integrator == Integrator::exact) {
    const BalancedExponential e = balanced_exponential(k_m, b_m, h, true);
    out.rest = unbalanced_map(e);
    xx = e.e.a[0][0];
    vv = e.e.a[1][1];
  } else {
    out.rest = map_for(p.integrator, k_m, b_m, h);
    xx = wide(out.rest.xx) - 1;
    vv = wide(out.rest.vv) - 1;
  }
  const auto split = [](Real less_one, double& rest, double& identity) {
    identity = less_one > -0.5L ? 1.0 : 0.0;
    rest = static_cast<double>(identity > 0.0 ? less_one : less_one + 1);
  };
  split(xx, out.rest.xx, out.identity_x);
  split(vv, out.rest.vv, out.identity_v);
  return out;
}

StepMap<double> linear_step_map(Integrator integrator, double stiffness_over_mass,
                                double damping_over_mass, double step_s) noexcept {
  return map_for(integrator, wide(stiffness_over_mass), wide(damping_over_mass), wide(step_s));
}

EventSearchPlan event_search_plan(const OscillatorParams& p, double epsilon) noexcept {
  const EventSearchPlan interpolate{kEventLevels, 0};
  if (p.integrator != Integrator::exact || !(p.mass_kg > 0.0)) return interpolate;
  // In the coordinates (omega0 x, v) the system matrix is [[0, omega0], [-omega0, -b/m]]: its
  // infinity norm omega0 + b/m bounds the growth of the Taylor coefficients, |c_n| <= rho^n/n!
  // times the state, rho = rate * tick.
  const double rate = std::sqrt(p.stiffness_n_per_m / p.mass_kg) + p.damping_ns_per_m / p.mass_kg;
  constexpr double kMaxRho = 1.0 / 16.0;
  int level = 0;
  double rho = rate * p.dt_s;
  while (rho > kMaxRho && level <= kEventLevels) {
    rho *= 0.5;
    ++level;
  }
  if (level > kEventLevels || !std::isfinite(rho)) return interpolate;
  // Smallest order whose first omitted term rho^(K+1)/(K+1)! is below epsilon/16.
  double term = rho * rho / 2.0;  // K = 1
  int order = 1;
  while (order < kMaxTaylorOrder && (order < 2 || term > epsilon / 16.0)) {
    ++order;
    term *= rho / static_cast<double>(order + 1);
  }
  return {level, order};
}

ConfigResult discretise(const OscillatorParams& p, DiscreteModel& out) noexcept {
  ConfigResult r;
  if (!check_parameters(p, r)) return r;
  const double k_m = p.stiffness_n_per_m / p.mass_kg;
  const double omega0 = std::sqrt(k_m);
  if (!check_event_step(p, omega0, r) || !check_euler_variants(p, omega0, r)) return r;
  double radius = 0.0;
  if (!check_stability(p, radius, r)) return r;
  fill_model(p, omega0, radius, out);
  return r;
}

}  // namespace stickslip
