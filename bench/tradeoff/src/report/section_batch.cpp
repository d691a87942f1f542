#include <algorithm>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "report/sections.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {
namespace {

using ProfilePair = std::pair<BatchProfile, BatchProfile>;  // batch, singles

// Instructions per lane-step of each profiled benchmark, common and event path apart.
void batch_profile_table(std::ostream& md, const std::vector<ProfilePair>& profiles) {
  md << "One run of each benchmark under `valgrind --tool=callgrind --toggle-collect='*run_batch*' "
        "--toggle-collect='*run_stream*'`: instructions per lane-step inside the loop, split into "
        "the loop "
        "function itself (the inlined common path: whole step stuck or slipping, and the "
        "statistics) and "
        "everything it calls out of line (the event search: Taylor segment, bracketed Newton, the "
        "event "
        "lanes' redo by their single oscillator).\n\n"
        "| benchmark | instructions/lane-step | common path (inlined) | event path (out of line) "
        "|\n"
        "|---|---|---|---|\n";
  for (const auto& [b, s] : profiles) {
    for (const BatchProfile* p : {&b, &s}) {
      md << fmt::format("| {} | {:.1f} | {:.1f} | {:.1f} |\n", p->name, p->total / p->lane_steps,
                        p->common_path / p->lane_steps,
                        (p->total - p->common_path) / p->lane_steps);
    }
  }
  md << "\n";
}

// Per pair: the event path that the batch cannot shrink, and the vectorised common path.
void batch_profile_bounds(std::ostream& md, const std::vector<ProfilePair>& profiles) {
  for (const auto& [b, s] : profiles) {
    const double b_common = b.common_path / b.lane_steps, s_common = s.common_path / s.lane_steps;
    const double b_event = (b.total - b.common_path) / b.lane_steps;
    const double s_total = s.total / s.lane_steps;
    const double amdahl = b_event > 0.0 ? s_total / b_event : 0.0;
    md << fmt::format(
        "- **{}**: the event path costs {:.1f} instructions per lane-step in the batch and {:.1f} "
        "in the "
        "singles: the batch redoes an event lane with the single oscillator's own code, so this "
        "part "
        "cannot shrink, and with it alone the batch could be at most {:.1f}x the singles' {:.1f} "
        "instructions/lane-step even if its common path were free (Amdahl). The vectorised common "
        "path "
        "takes {:.1f} instructions per lane-step against the scalar path's {:.1f} (ratio {:.2f}): "
        "it computes "
        "both candidates (a whole step stuck and a whole step slipping) for every lane and selects "
        "by "
        "bit masks, and the default x86-64 target (SSE2) holds only {} {}s per vector.\n",
        b.name, b_event, (s.total - s.common_path) / s.lane_steps, amdahl, s_total, b_common,
        s_common, s_common > 0.0 ? b_common / s_common : 0.0,
        b.name.find("/float/") != std::string::npos ? 4 : 2,
        b.name.find("/float/") != std::string::npos ? "float" : "double");
  }
}

// The same benchmarks built for AVX2, and what would close the gap.
void batch_profile_outlook(std::ostream& md, const ReportRequest& request,
                           const std::vector<BatchResult>& batches) {
  const std::vector<BatchResult> avx2 = batch_speedups(read_text(request.bench_step_avx2_json));
  if (!avx2.empty()) {
    std::string measured;
    double best = 0.0;
    for (const BatchResult& r : avx2) {
      measured += fmt::format("{}{}: {}", measured.empty() ? "" : "; ", r.name, times(r.speedup));
      best = std::max(best, r.speedup);
    }
    double best_default = 0.0;
    for (const BatchResult& r : batches) best_default = std::max(best_default, r.speedup);
    md << fmt::format(
        "- **Built for AVX2** (`-DSTICKSLIP_ARCH=x86-64-v3`: 4 doubles or 8 floats per vector, FMA "
        "contraction off), the same benchmarks in the same report run: {} (best {}{}).\n",
        measured, times(best),
        best_default > 0.0
            ? fmt::format(", against {} with the default target", times(best_default))
            : std::string());
  } else {
    md << "- The AVX2 build was not measured in this run (the CPU lacks AVX2/FMA or the build "
          "failed).\n";
  }
  md << "- **What would close it:** (1) a vectorised event search (the Taylor-segment root finder "
        "run "
        "across lanes under masks) so that the ~1 % event lane-steps no longer drop to scalar code "
        "— "
        "without it the event path alone caps the ratio as computed above; (2) one candidate per "
        "lane "
        "instead of two (branch-free formulation of stuck and slipping as one affine map with "
        "per-lane coefficients); (3) wider vectors (AVX2/AVX-512 builds) for what remains. None of "
        "these "
        "changes the results, which the batch tests pin bit for bit to the single oscillator.\n\n";
}

}  // namespace

void section_bench_step(std::ostream& md, const std::string& bench_text) {
  md << "## Batch mode (stickslip_bench_step)\n\n";
  if (bench_text.empty()) {
    md << "`stickslip_bench_step` was not built when this report ran, so the batch target is not "
          "measured.\n\n";
  } else {
    // The medians only (the run has repetitions; mean, stddev and cv are in the JSON).
    std::istringstream lines(bench_text);
    std::string line, kept;
    while (std::getline(lines, line)) {
      if (line.find("_mean ") != std::string::npos || line.find("_stddev ") != std::string::npos ||
          line.find("_cv ") != std::string::npos) {
        continue;
      }
      kept += line + "\n";
    }
    md << "`stickslip_bench_step` (Google Benchmark, bench/step/) as this report ran it, median "
          "aggregates:\n\n```\n"
       << kept << "```\n\n";
    if (kept.find("Library was built as DEBUG") != std::string::npos) {
      md << "(Google Benchmark's warning \"Library was built as DEBUG\" is about Debian's "
            "libbenchmark "
            "itself, which only drives the loop; the timed code is the project's release "
            "build.)\n\n";
    }
  }
}

// Why batch mode falls short of the 4x target, from callgrind counts of one run of each benchmark.
void section_batch_profile(std::ostream& md, const ReportRequest& request,
                           const std::vector<BatchResult>& batches) {
  if (request.batch_profile_dir.empty()) return;
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"batch/double/N8/own-inputs", "singles/double/N8/own-inputs"},
      {"batch/float/N16/own-inputs", "singles/float/N16/own-inputs"}};
  std::vector<ProfilePair> profiles;
  for (const auto& [batch, single] : pairs) {
    BatchProfile b = read_batch_profile(request.batch_profile_dir, batch);
    BatchProfile s = read_batch_profile(request.batch_profile_dir, single);
    if (b.ok() && s.ok()) profiles.emplace_back(b, s);
  }
  md << "### Why the batch target is missed (callgrind)\n\n";
  if (profiles.empty()) {
    md << "The batch profile did not run (valgrind or the benchmark missing), so the miss is not "
          "profiled here.\n\n";
    return;
  }
  batch_profile_table(md, profiles);
  batch_profile_bounds(md, profiles);
  batch_profile_outlook(md, request, batches);
}

}  // namespace stickslip::tradeoff::report
