#include "tradeoff/runner.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <ostream>

#include <fmt/format.h>

#include "stickslip/host/error.hpp"
#include "tradeoff/callgrind_dumps.hpp"
#include "tradeoff/csv_table.hpp"
#include "tradeoff/measure.hpp"
#include "tradeoff/peers.hpp"
#include "tradeoff/reference.hpp"
#include "tradeoff/scenes.hpp"

namespace stickslip::tradeoff {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Row scene_row(const Scene& scene, const Plan& plan, double dt_ms, std::size_t steps) {
  Row row;
  row.scene = scene.name;
  row.kind = host::signal_kind_name(scene.kind);
  row.friction = friction_name(scene.friction);
  row.den_hartog_k = scene.den_hartog_k;
  row.damping_ns_per_m = scene.physics.damping_ns_per_m;
  row.kinetic_friction_n = scene.physics.kinetic_friction_n;
  row.static_friction_n = scene.physics.static_friction_n;
  row.duration_s = plan.scenes.duration_s;
  row.dt_ms = dt_ms;
  row.steps = steps;
  return row;
}

void fill_outcome(Row& row, const Outcome& outcome, const Reference& physics, const Reference& own,
                  bool friction_scene) {
  row.status = outcome.status;
  row.note = outcome.note;
  row.t_ax_ref = physics.transmissibility;
  if (friction_scene) row.p_ref = physics.stick_probability;
  if (!outcome.timing) return;
  row.ns_median = outcome.timing->median_ns;
  row.ns_min = outcome.timing->min_ns;
  row.ns_max = outcome.timing->max_ns;
  row.repetitions = outcome.timing->repetitions;
  const RunTrace& trace = outcome.trace;
  const Errors vs_physics = compare(trace, physics);
  const Errors vs_own = &own == &physics ? vs_physics : compare(trace, own);
  row.t_ax = trace.transmissibility;
  row.t_ax_rel_err = vs_physics.transmissibility_rel;
  if (trace.has_stick_state) row.p = trace.stick_probability;
  if (vs_physics.stick_prob_abs) row.p_abs_err = *vs_physics.stick_prob_abs;
  row.a_x_rms_err = vs_physics.a_x_rms;
  row.a_x_rms_err_rel = vs_physics.a_x_rms_rel;
  row.x_r_rms_err = vs_physics.x_r_rms;
  row.x_r_rms_err_rel = vs_physics.x_r_rms_rel;
  row.solver_t_ax_rel_err = vs_own.transmissibility_rel;
  row.solver_a_x_rms_err_rel = vs_own.a_x_rms_rel;
  row.solver_x_r_rms_err_rel = vs_own.x_r_rms_rel;
  row.events = static_cast<double>(trace.events);
}

// Signals are generated once per kind and scenes come grouped by kind.
class SignalCache {
 public:
  explicit SignalCache(const SceneOptions& options) : options_(options) {}
  const std::vector<double>& get(host::SignalKind kind) {
    if (!has_ || kind != kind_) {
      signal_ = generate_base_signal(kind, options_);
      kind_ = kind;
      has_ = true;
    }
    return signal_;
  }

 private:
  const SceneOptions& options_;
  std::vector<double> signal_;
  host::SignalKind kind_{};
  bool has_ = false;
};

// The reference solver refuses what the core's configure() refuses with the exact integrator (e.g.
// a dt beyond the event search's limit): say for which scene and dt.
Reference reference_for(const Scene& scene, const OscillatorParams& params,
                        const std::vector<double>& a_u) {
  try {
    return compute_reference(params, a_u);
  } catch (const host::HostError& error) {
    throw host::UsageError(fmt::format("the reference of {} ({}) at dt = {:g} ms: {}", scene.name,
                                       model_name(params.model), params.dt_s * 1e3, error.what()));
  }
}

SampledInput sampled(const std::vector<double>& base, double dt_ms) {
  const std::size_t stride = stride_for_dt_ms(dt_ms);
  SampledInput input;
  input.as_double = sample_every<double>(base, stride);
  input.as_float = sample_every<float>(base, stride);
  if (input.as_double.size() < 3) {
    throw host::UsageError(fmt::format("--dt {:g} ms: the {:g} s scene gives fewer than 3 samples",
                                       dt_ms, static_cast<double>(base.size() - 1) * kBaseDtS));
  }
  return input;
}

}  // namespace

namespace {

// The references of one scene at one dt: the physics, and each smoothed law's own, solved when
// first needed; the time spent solving them accumulates in `reference_s`.
class DtReferences {
 public:
  DtReferences(const Scene& scene, double dt_ms, const SampledInput& input, double& reference_s)
      : scene_(scene),
        dt_ms_(dt_ms),
        input_(input),
        reference_s_(reference_s),
        physics_(reference_for(scene, physics_params(scene, dt_ms), input.as_double)) {
    reference_s_ += physics_.solve_seconds;
  }
  const Reference& physics() const { return physics_; }
  const Reference& own(const ModelChoice& model) {
    if (!own_reference_differs(scene_, model)) return physics_;
    auto found = own_references_.find(model.smoothing);
    if (found == own_references_.end()) {
      found = own_references_
                  .emplace(model.smoothing,
                           reference_for(scene_, own_reference_params(scene_, model, dt_ms_),
                                         input_.as_double))
                  .first;
      reference_s_ += found->second.solve_seconds;
    }
    return found->second;
  }

 private:
  const Scene& scene_;
  const double dt_ms_;
  const SampledInput& input_;
  double& reference_s_;
  const Reference physics_;
  std::map<SmoothingLaw, Reference> own_references_;
};

// Our runs of one scene at one dt: every model x integrator x scalar of the plan that runs there.
std::size_t write_library_rows(std::ostream& out, const Plan& plan, const Scene& scene,
                               double dt_ms, const SampledInput& input, DtReferences& references,
                               const std::map<std::string, double>& instructions) {
  const std::size_t steps = input.as_double.size() - 1;
  const bool friction_scene = scene.friction != SceneFriction::none;
  const Reference& physics = references.physics();
  std::size_t rows = 0;
  for (const ModelChoice& model : plan.models) {
    if (!runs_in_scene(model, scene) || !runs_at_dt(model, dt_ms, plan)) continue;
    const Reference& own = references.own(model);
    for (const Integrator integrator : plan.integrators) {
      for (const host::ScalarType scalar : plan.scalars) {
        const OscillatorParams params = run_params(scene, model, integrator, dt_ms);
        const Outcome outcome = run_library(params, scalar, input, physics, plan.timing);
        Row row = scene_row(scene, plan, dt_ms, steps);
        row.implementation = "stickslip";
        row.model = model.name;
        row.integrator = integrator_name(integrator);
        row.scalar = host::scalar_name(scalar);
        fill_outcome(row, outcome, physics, own, friction_scene);
        const auto counted = instructions.find(
            combination_key(scene.name, row.model, row.integrator, row.scalar, dt_ms));
        if (outcome.timing && counted != instructions.end()) row.ir_per_sample = counted->second;
        write_row(out, row);
        ++rows;
      }
    }
  }
  return rows;
}

// The Boost.Odeint peers on one Coulomb scene at one dt.
std::size_t write_peer_rows(std::ostream& out, const Plan& plan, const Scene& scene, double dt_ms,
                            const SampledInput& input, DtReferences& references) {
  const std::size_t steps = input.as_double.size() - 1;
  const Reference& physics = references.physics();
  std::size_t rows = 0;
  for (const PeerSpec& peer : plan.peers) {
    ModelChoice smooth;
    smooth.name = "smooth-tanh";
    smooth.model = FrictionModel::smooth;
    const bool smooth_peer = peer.kind != PeerKind::dopri5_events;
    const Reference& own = smooth_peer ? references.own(smooth) : physics;
    const OscillatorParams params = physics_params(scene, dt_ms);
    const Outcome outcome = run_peer(peer, params, input.as_double, physics, plan.peer_timing);
    Row row = scene_row(scene, plan, dt_ms, steps);
    row.implementation = "odeint";
    row.model = peer_model_name(peer.kind);
    row.integrator = peer_integrator_name(peer.kind);
    row.scalar = "double";
    if (peer_uses_tolerance(peer.kind)) row.tolerance = peer.tolerance;
    fill_outcome(row, outcome, physics, own, true);
    write_row(out, row);
    ++rows;
  }
  return rows;
}

void write_results(const RunRequest& request, std::ostream& out, std::ostream& progress) {
  const Plan& plan = request.plan;
  const auto started = Clock::now();
  std::map<std::string, double> instructions;
  if (!request.instructions_dir.empty()) {
    instructions = read_instruction_counts(request.instructions_dir);
  }
  write_header(out);

  const std::vector<Scene> scenes = make_scenes(plan.scenes);
  SignalCache signals(plan.scenes);
  std::size_t rows = 0;
  for (const Scene& scene : scenes) {
    const std::vector<double>& base = signals.get(scene.kind);
    const auto scene_start = Clock::now();
    double reference_s = 0.0;
    for (const double dt_ms : plan.dts_ms) {
      const SampledInput input = sampled(base, dt_ms);
      DtReferences references(scene, dt_ms, input, reference_s);
      rows += write_library_rows(out, plan, scene, dt_ms, input, references, instructions);
      if (scene.friction == SceneFriction::coulomb)
        rows += write_peer_rows(out, plan, scene, dt_ms, input, references);
      out.flush();
    }
    progress << fmt::format("{:>28}: {:5.1f} s, of which references {:4.1f} s ({:.0f} s so far)\n",
                            scene.name, seconds_since(scene_start), reference_s,
                            seconds_since(started))
             << std::flush;
  }
  progress << fmt::format("{} rows in {:.1f} s -> {}\n", rows, seconds_since(started),
                          request.output_csv);
}

}  // namespace

void run_harness(const RunRequest& request, std::ostream& progress) {
  // Written to a temporary file, renamed when complete: a failed run leaves nothing behind.
  const std::string temporary = request.output_csv + ".partial";
  std::ofstream out(temporary);
  if (!out) throw host::HostError(temporary + ": cannot open for writing");
  try {
    write_results(request, out, progress);
    out.close();
    if (!out) throw host::HostError(temporary + ": write failed");
  } catch (...) {
    out.close();
    std::remove(temporary.c_str());
    throw;
  }
  if (std::rename(temporary.c_str(), request.output_csv.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw host::HostError(request.output_csv + ": cannot replace");
  }
}

void count_instructions(const Plan& plan, std::ostream& progress) {
#ifndef STICKSLIP_HAVE_CALLGRIND_H
  throw host::UsageError(
      "count-instructions: built without valgrind/callgrind.h (install valgrind and rebuild)");
#endif
  if (!running_on_valgrind()) {
    throw host::UsageError(
        "count-instructions counts with callgrind client requests: run it as valgrind "
        "--tool=callgrind --instr-atstart=no stickslip_tradeoff count-instructions ...");
  }
  const auto started = Clock::now();
  const std::vector<Scene> scenes = make_scenes(plan.scenes);
  SignalCache signals(plan.scenes);
  std::size_t counted = 0;
  for (const Scene& scene : scenes) {
    const std::vector<double>& base = signals.get(scene.kind);
    for (const double dt_ms : plan.dts_ms) {
      const SampledInput input = sampled(base, dt_ms);
      for (const ModelChoice& model : plan.models) {
        if (!runs_in_scene(model, scene) || !runs_at_dt(model, dt_ms, plan)) continue;
        for (const Integrator integrator : plan.integrators) {
          for (const host::ScalarType scalar : plan.scalars) {
            const std::size_t steps =
                plan.instruction_steps > 0 ? plan.instruction_steps : input.as_double.size();
            const std::string key =
                combination_key(scene.name, model.name, integrator_name(integrator),
                                host::scalar_name(scalar), dt_ms);
            if (count_library(run_params(scene, model, integrator, dt_ms), scalar, input, steps,
                              key)) {
              ++counted;
            }
          }
        }
      }
    }
    progress << fmt::format("{:>28}: counted ({:.0f} s so far)\n", scene.name,
                            seconds_since(started))
             << std::flush;
  }
  progress << fmt::format("{} combinations counted in {:.1f} s\n", counted, seconds_since(started));
}

}  // namespace stickslip::tradeoff
