#include "soak/scene.hpp"

#include <cmath>

#include "stickslip/host/signals/signal_generator.hpp"

namespace stickslip::soak {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

template <typename T>
Scene<T> lorry_scene() {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::lorry;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = 600.0;
  spec.dt_s = 1e-3;
  spec.seed = 1;
  const std::vector<double> recording = host::generate_signal(spec);
  Scene<T> scene;
  scene.input.assign(recording.begin(), recording.end() - 1);  // a loop: last sample = first period
  OscillatorParams& p = scene.params;
  p.model = FrictionModel::stick_slip;
  p.integrator = Integrator::exact;
  p.dt_s = spec.dt_s;
  p.kinetic_friction_n = 0.8 * kPi * std::sqrt(2.0) * p.mass_kg * spec.rms_m_per_s2 / 4.0;
  p.static_friction_n = p.kinetic_friction_n;
  return scene;
}

template Scene<float> lorry_scene<float>();
template Scene<double> lorry_scene<double>();

}  // namespace stickslip::soak
