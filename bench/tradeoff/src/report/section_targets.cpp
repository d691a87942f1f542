#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "report/sections.hpp"
#include "report/targets.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {
namespace {

// Cost of stick-slip / exact / double.
void cost_target(Table& t, const Results& results, const Row* headline,
                 const CallgrindDump& profile) {
  std::vector<double> all_scenes;
  double worst = 0.0;
  std::string worst_scene;
  for (const Row& r : results.rows) {
    if (r.implementation == "stickslip" && r.model == "stick-slip" && r.integrator == "exact" &&
        r.scalar == "double" && same_dt(r.dt_ms, kHeadlineDtMs) && r.ns_median) {
      all_scenes.push_back(*r.ns_median);
      if (*r.ns_median > worst) {
        worst = *r.ns_median;
        worst_scene = r.scene;
      }
    }
  }
  if (headline && headline->ns_median) {
    const double got = *headline->ns_median;
    std::string measured = fmt::format(
        "**{} ns/sample** median on {} at 1 ms ({:.0f} repetitions: fastest {}, slowest {})",
        ns(got), kHeadlineScene, headline->repetitions.value_or(0),
        ns(headline->ns_min.value_or(0)), ns(headline->ns_max.value_or(0)));
    if (profile.steps > 0.0) {
      measured += fmt::format(", {:.0f} instructions/sample (callgrind, whole scene)",
                              profile.self_total / profile.steps);
    } else if (headline->ir_per_sample) {
      measured += fmt::format(", {:.0f} instructions/sample", *headline->ir_per_sample);
    }
    measured +=
        fmt::format("; over the {} Coulomb scenes at 1 ms: {}–{} ns, median {} (slowest {})",
                    all_scenes.size(), ns(*std::min_element(all_scenes.begin(), all_scenes.end())),
                    ns(worst), ns(median_of(all_scenes)), worst_scene);
    std::string verdict = met(got <= kTargetNsPerSample);
    if (got > kTargetNsPerSample) {
      verdict += fmt::format(" by {} ns ({:.0f} %); see *Where the time goes*",
                             ns(got - kTargetNsPerSample),
                             100.0 * (got - kTargetNsPerSample) / kTargetNsPerSample);
    }
    t.rows.push_back(
        {"stick-slip, exact, double, streaming (step + statistics, no I/O): <= 10 ns/sample median",
         measured, verdict});
  } else {
    t.rows.push_back({"stick-slip, exact, double: <= 10 ns/sample", "not in this run", "–"});
  }
}

// Accuracy at dt = 1 ms on the lorry-like scenes.
void accuracy_target(Table& t, const Results& results, const Row* headline) {
  double worst_tax = 0.0, worst_p = 0.0;
  std::string worst_tax_scene, worst_p_scene;
  int lorry_runs = 0;
  for (const Row& r : results.rows) {
    if (r.implementation != "stickslip" || r.kind != "lorry" || r.model != "stick-slip" ||
        r.integrator != "exact" || r.scalar != "double" || !same_dt(r.dt_ms, kHeadlineDtMs) ||
        !r.ok()) {
      continue;
    }
    ++lorry_runs;
    if (r.t_ax_rel_err && *r.t_ax_rel_err >= worst_tax) {
      worst_tax = *r.t_ax_rel_err;
      worst_tax_scene = r.scene;
    }
    if (r.p_abs_err && *r.p_abs_err >= worst_p) {
      worst_p = *r.p_abs_err;
      worst_p_scene = r.scene;
    }
  }
  if (headline && lorry_runs > 0) {
    t.rows.push_back(
        {"dt = 1 ms, lorry-like scene: T_ax within 0.1 % and p within 0.005 of the reference",
         fmt::format("{}: T_ax error {}, p error {}; worst over the {} lorry Coulomb scenes (K, "
                     "b): T_ax {} ({}), "
                     "p {} ({})",
                     kHeadlineScene, opt_sci(headline->t_ax_rel_err), opt_sci(headline->p_abs_err),
                     lorry_runs, sci(worst_tax), worst_tax_scene, sci(worst_p), worst_p_scene),
         met(worst_tax <= kTargetTaxRelErr && worst_p <= kTargetPAbsErr)});
  }
}

// Against the fastest Odeint peer at the same T_ax error.
void peer_target(Table& t, const Results& results, const Row* headline) {
  if (headline && headline->ok() && headline->t_ax_rel_err) {
    const double ours_err = *headline->t_ax_rel_err, ours_ns = *headline->ns_median;
    const Row *same = nullptr, *band = nullptr, *most_accurate = nullptr;
    for (const Row& r : results.rows) {
      if (r.implementation != "odeint" || r.scene != kHeadlineScene ||
          !same_dt(r.dt_ms, kHeadlineDtMs) || !r.ok() || !r.t_ax_rel_err || !r.ns_median) {
        continue;
      }
      if (*r.t_ax_rel_err <= ours_err && (!same || *r.ns_median < *same->ns_median)) same = &r;
      if (*r.t_ax_rel_err <= kTargetTaxRelErr && (!band || *r.ns_median < *band->ns_median))
        band = &r;
      if (!most_accurate || *r.t_ax_rel_err < *most_accurate->t_ax_rel_err) most_accurate = &r;
    }
    std::string measured;
    double ratio = 0.0;
    if (same) {
      ratio = *same->ns_median / ours_ns;
      measured =
          fmt::format("fastest peer with a T_ax error <= ours ({}): {} at {} ns/sample -> **{}**",
                      sci(ours_err), same->configuration(), ns(*same->ns_median), times(ratio));
    } else if (most_accurate) {
      ratio = *most_accurate->ns_median / ours_ns;
      measured = fmt::format(
          "no peer reaches our T_ax error ({}); the most accurate, {} ({} ns/sample, error {}), is "
          "**{}** "
          "slower",
          sci(ours_err), most_accurate->configuration(), ns(*most_accurate->ns_median),
          opt_sci(most_accurate->t_ax_rel_err), times(ratio));
    }
    if (band) {
      measured += fmt::format("; the fastest peer inside the 0.1 % band is {} at {} ns/sample: {}",
                              band->configuration(), ns(*band->ns_median),
                              times(*band->ns_median / ours_ns));
    }
    std::string verdict =
        measured.empty() ? "not measured (no peer run)" : met(ratio >= kTargetPeerRatio);
    if (!measured.empty() && ratio < kTargetPeerRatio) {
      verdict += fmt::format(" ({} of 50x); see *Peers*", times(ratio));
    }
    t.rows.push_back(
        {fmt::format(">= 50x faster than the fastest Boost.Odeint peer that reaches the same T_ax "
                     "error ({}, 1 ms)",
                     kHeadlineScene),
         measured.empty() ? "–" : measured, verdict});
  }
}

// Batch mode (helper benchmark).
void batch_target(Table& t, const std::vector<BatchResult>& batches, bool bench_step_ran) {
  if (!bench_step_ran) {
    t.rows.push_back({"batch mode >= 4x single-oscillator throughput",
                      "`stickslip_bench_step` was not built when this report ran", "not measured"});
  } else if (batches.empty()) {
    t.rows.push_back(
        {"batch mode >= 4x single-oscillator throughput",
         "`stickslip_bench_step` ran but has no batch/<scalar>/N<lanes> benchmark with a "
         "singles/<scalar>/N<lanes> partner (its output is below)",
         "not measured"});
  } else {
    std::string measured;
    double best = 0.0;
    for (const BatchResult& b : batches) {
      measured += fmt::format("{}{}: {}", measured.empty() ? "" : "; ", b.name, times(b.speedup));
      best = std::max(best, b.speedup);
    }
    t.rows.push_back(
        {"batch mode >= 4x single-oscillator throughput (items/s of batch/<scalar>/N over "
         "singles/<scalar>/N on the same inputs, `stickslip_bench_step` medians)",
         measured, met(best >= kTargetBatchSpeedup) + fmt::format(" (best {})", times(best))});
  }
}

}  // namespace

void section_targets(std::ostream& md, const Results& results,
                     const std::vector<BatchResult>& batches, bool bench_step_ran,
                     const CallgrindDump& profile) {
  md << "## Targets\n\n";
  Table t;
  t.header = {"target", "measured", "verdict"};

  const Row* headline =
      results.find(kHeadlineScene, "stick-slip", "exact", "double", kHeadlineDtMs);
  cost_target(t, results, headline, profile);
  accuracy_target(t, results, headline);
  peer_target(t, results, headline);
  batch_target(t, batches, bench_step_ran);
  t.write(md);
}

}  // namespace stickslip::tradeoff::report
