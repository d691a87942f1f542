// Random seats with end stops and the hostile floors that drive them, for the tests of the
// end-stop seat's event search (test_end_stops.cpp, test_end_stop_event_budget.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "oracles.hpp"
#include "stickslip/models/end_stops.hpp"

namespace stickslip::test {

// A random seat (random_sticking_seat()) with stops 5-55 mm out, omega dt in contact from 0.02 to
// 1.4 and their damping 0 (two in five) or up to 3000 N s/m.
struct RandomStopSeat {
  OscillatorParams seat;
  EndStopParams stops;
};

inline RandomStopSeat random_stop_seat(SplitMix64& random, FrictionModel model) {
  RandomStopSeat r;
  r.seat = random_sticking_seat(random, model);
  const OscillatorParams& p = r.seat;
  r.stops.travel_m = random.uniform(0.005, 0.055);
  const double contact_rate = random.uniform(0.02, 1.4) / p.dt_s;  // omega in contact
  r.stops.stiffness_n_per_m =
      std::max(1.0e4, contact_rate * contact_rate * p.mass_kg - p.stiffness_n_per_m);
  r.stops.damping_ns_per_m = random.uniform(0.0, 1.0) < 0.4 ? 0.0 : random.uniform(0.0, 3000.0);
  return r;
}

// Float forms the stop's force in contact from k_s x and k_s travel, so it resolves the force at
// the stop to about eps k_s travel: the seats whose friction float can tell from that rounding,
// 16 eps k_s travel <= F_fs / 16 (DESIGN.md, "Rounding at the break-away threshold").
inline bool float_resolves_the_friction_at_the_stop(const RandomStopSeat& r) {
  const double rounding_n = 16.0 * static_cast<double>(std::numeric_limits<float>::epsilon()) *
                            r.stops.stiffness_n_per_m * r.stops.travel_m;
  return rounding_n <= r.seat.static_friction_n / 16.0;
}

// The floor of sample n, chosen from the seat's state (x_r, v_r and the stop's force on it) in
// phases of 0.3 s: white noise up to 30 m/s^2; a drive to either stop (a critically damped
// approach at 10 Hz to its edge +-10 % with a force up to 2 F_fs); the limit force held on +-F_fs
// (alternating every 7 samples, offsets down to 1e-8 m/s^2), at a stop or free; swings of 1.5 to
// 9.5 F_fs. 0 where the seat was thrown so far into a stiff stop that the floor would exceed
// 200 m/s^2.
inline double hostile_stop_floor(const RandomStopSeat& r, long n, double x_r, double v_r,
                                 double stop_force_n, SplitMix64& random) {
  const double m = r.seat.mass_kg, f_fs = r.seat.static_friction_n, w = 2.0 * kPi * 10.0;
  const double holding = -(r.seat.stiffness_n_per_m * x_r + stop_force_n) / m;
  double a_u = 0.0;
  switch ((n / 300) % 4) {
    case 0:
      a_u = hostile_floor(HostileFloor::noise, n, holding, f_fs / m, random);
      break;
    case 1: {
      const double side = (n / 900) % 2 == 0 ? -1.0 : 1.0;
      const double edge = side * r.stops.travel_m * random.uniform(0.9, 1.1);
      a_u = w * w * (x_r - edge) + 2.0 * w * v_r + holding + 2.0 * f_fs / m * random.uniform(-1, 1);
      break;
    }
    case 2:
      a_u = hostile_floor(HostileFloor::threshold, n, holding, f_fs / m, random);
      break;
    default:
      a_u = hostile_floor(HostileFloor::swing, n, holding, f_fs / m, random);
  }
  return std::fabs(a_u) <= 200.0 ? a_u : 0.0;
}

}  // namespace stickslip::test
