// What the harness runs: the plan (scenes, models, integrators, scalars, dt lists, peers, timing)
// parsed from comma-separated lists, and which combination runs in which scene.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "tradeoff/scenes.hpp"

namespace stickslip::tradeoff {

// A friction model as the harness names it: the smoothed signum comes with its law
// ("smooth-tanh"; "smooth" is accepted as the tanh form).
struct ModelChoice {
  std::string name;
  FrictionModel model = FrictionModel::stick_slip;
  SmoothingLaw smoothing = SmoothingLaw::tanh;
};

// Boost.Odeint peers: how a user would solve the scene without this library.
enum class PeerKind : unsigned char {
  rk4_smooth,     // runge_kutta4, one fixed step per sample, smoothed signum (tanh, c = 1000)
  dopri5_smooth,  // controlled runge_kutta_dopri5 over each sample interval, the same model
  dopri5_events,  // controlled dopri5 + bisection on v_r = 0 and |F_L| = F_fs, stick-slip
};
const char* peer_integrator_name(PeerKind kind) noexcept;  // "odeint-rk4", ...
const char* peer_model_name(PeerKind kind) noexcept;       // "smooth-tanh" or "stick-slip"
bool peer_uses_tolerance(PeerKind kind) noexcept;

struct PeerSpec {
  PeerKind kind = PeerKind::rk4_smooth;
  double tolerance = 0.0;  // absolute = relative error tolerance of the controlled steppers
};

struct Timing {
  int repetitions = 5;             // timed repetitions; the median is reported
  double min_repetition_s = 2e-3;  // a repetition loops over the input until at least this long
};

struct Plan {
  SceneOptions scenes;
  std::vector<ModelChoice> models;
  std::vector<Integrator> integrators;
  std::vector<host::ScalarType> scalars;
  std::vector<double> dts_ms;
  // The smoothing laws other than tanh run at these dt only (they differ from tanh in cost, not
  // in kind).
  std::vector<double> other_laws_dts_ms;
  std::vector<PeerSpec> peers;
  Timing timing;
  Timing peer_timing{3, 2e-3};
  std::size_t instruction_steps = 4000;  // count-instructions: steps per combination (0: all)
};

// Parsers for the command line; each throws host::UsageError naming the bad item and the known
// names. Lists are comma-separated; empty lists are refused.
std::vector<ModelChoice> parse_models(const std::string& list);
std::vector<Integrator> parse_integrators(const std::string& list);
std::vector<host::ScalarType> parse_scalars(const std::string& list);
std::vector<double> parse_dts_ms(const std::string& list);  // each a whole multiple of 0.05 ms
std::vector<host::SignalKind> parse_kinds(const std::string& list);
std::vector<SceneFriction> parse_frictions(const std::string& list);
std::vector<double> parse_numbers(const std::string& what, const std::string& list, double min,
                                  bool min_inclusive);
std::vector<PeerSpec> parse_peers(const std::string& list, const std::vector<double>& tolerances);

// The scene physics a model is compared with: linear models in frictionless scenes, signum,
// smoothed and stick-slip models in Coulomb scenes, Stribeck in Stribeck scenes.
bool runs_in_scene(const ModelChoice& model, const Scene& scene) noexcept;
bool runs_at_dt(const ModelChoice& model, double dt_ms, const Plan& plan) noexcept;

// Parameters of a run: the scene's physics with the model, law, integrator and dt.
OscillatorParams run_params(const Scene& scene, const ModelChoice& model, Integrator integrator,
                            double dt_ms);
// The physically correct reference of the scene at dt (its own model, exact events).
OscillatorParams physics_params(const Scene& scene, double dt_ms);
// The model's own reference (the "solver error"): the same law solved tightly. Signum's exact
// Filippov solution is stick-slip with F_fs = F_fk, so it equals the physics reference there.
OscillatorParams own_reference_params(const Scene& scene, const ModelChoice& model, double dt_ms);
bool own_reference_differs(const Scene& scene, const ModelChoice& model) noexcept;

// Identifies a combination across the timed run and the callgrind run.
std::string combination_key(const std::string& scene, const std::string& model,
                            const std::string& integrator, const std::string& scalar, double dt_ms);

}  // namespace stickslip::tradeoff
