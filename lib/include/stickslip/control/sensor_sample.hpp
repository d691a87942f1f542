// What a seat controller reads at a sample: the plant's sensors (ISO 2631 sign: upward positive)
// and the absolute velocities a controller of the hook family needs, estimated from the
// accelerations (AbsoluteVelocity below) since neither is measured directly.
#pragma once

namespace stickslip {

template <typename T>
struct SensorSample {
  T a_u_m_per_s2;         // cab floor acceleration
  T a_x_m_per_s2;         // seat acceleration
  T x_r_m;                // seat travel relative to the floor
  T v_r_m_per_s;          // relative velocity (seat - floor)
  T v_seat_m_per_s;       // absolute seat velocity (estimated)
  T v_floor_m_per_s;      // absolute floor velocity (estimated)
  T friction_estimate_n;  // the observer's friction estimate (0 without one)
};

}  // namespace stickslip
