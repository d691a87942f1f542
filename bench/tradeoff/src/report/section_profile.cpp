#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "report/profile_source.hpp"
#include "report/sections.hpp"
#include "report/targets.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {
namespace {

// The functions with the largest self cost.
void hot_functions(std::ostream& md, const CallgrindDump& profile) {
  std::vector<std::pair<double, std::string>> functions;
  for (const auto& [name, ir] : profile.functions) functions.emplace_back(ir, name);
  std::sort(functions.rbegin(), functions.rend());
  Table f;
  f.header = {"instructions/sample", "share", "function"};
  for (std::size_t i = 0; i < functions.size() && i < 6 && functions[i].first > 0.0; ++i) {
    f.rows.push_back({fmt::format("{:.1f}", functions[i].first / profile.steps),
                      fmt::format("{:.1f} %", 100.0 * functions[i].first / profile.self_total),
                      "`" + short_function(functions[i].second) + "`"});
  }
  f.write(md);
}

// The source lines with the largest self cost, then the totals by source file.
void hot_lines(std::ostream& md, const CallgrindDump& profile) {
  md << "The source lines that execute the most instructions (self cost, inlined code at its own "
        "line):\n\n";
  std::vector<std::pair<double, std::pair<std::string, long>>> hot;
  for (const auto& [where, ir] : profile.lines) hot.emplace_back(ir, where);
  std::sort(hot.rbegin(), hot.rend());
  Table t;
  t.header = {"instructions/sample", "share", "where", "code"};
  std::map<std::string, double> by_file;
  for (const auto& [where, ir] : profile.lines) by_file[repository_path(where.first)] += ir;
  for (std::size_t i = 0; i < hot.size() && i < 16; ++i) {
    const auto& [ir, where] = hot[i];
    t.rows.push_back({fmt::format("{:.2f}", ir / profile.steps),
                      fmt::format("{:.1f} %", 100.0 * ir / profile.self_total),
                      fmt::format("{}:{}", repository_path(where.first), where.second),
                      "`" + source_line(where.first, where.second) + "`"});
  }
  t.write(md);
  md << "By source file:";
  std::vector<std::pair<double, std::string>> files;
  for (const auto& [file, ir] : by_file) files.emplace_back(ir, file);
  std::sort(files.rbegin(), files.rend());
  for (std::size_t i = 0; i < files.size() && i < 6; ++i) {
    md << fmt::format("{} `{}` {:.1f} ({:.0f} %)", i ? ";" : "", files[i].second,
                      files[i].first / profile.steps, 100.0 * files[i].first / profile.self_total);
  }
  md << " instructions/sample.\n\n";
}

// Which part of a sample is the unavoidable work and which is the event machinery, by the
// source text of the lines: the affine map, the running statistics, the non-finite guards.
void target_miss(std::ostream& md, const CallgrindDump& profile, const Row& headline,
                 double per_step) {
  double affine = 0.0, statistics = 0.0, guards = 0.0;
  for (const auto& [where, ir] : profile.lines) {
    const std::string file = repository_path(where.first);
    const std::string code = source_line(where.first, where.second);
    if (file.find("statistics") != std::string::npos) {
      statistics += ir;
    } else if (code.find("is_finite") != std::string::npos ||
               code.find("isfinite") != std::string::npos ||
               code.find("guard_state") != std::string::npos ||
               code.find("infinity") != std::string::npos) {
      guards += ir;
    } else if (code.find("m.xx *") != std::string::npos ||
               code.find("m.vx *") != std::string::npos) {
      affine += ir;
    }
  }
  const double rest = profile.self_total - affine - statistics - guards;
  const double ipc_ns = per_step / *headline.ns_median;  // instructions per ns as measured
  const double needed = kTargetNsPerSample * ipc_ns;
  const double essential = (affine + statistics + guards) / profile.steps;
  double search = 0.0;  // the in-step event search, when it is a function of its own
  for (const auto& [name, ir] : profile.functions) {
    if (short_function(name).find("::slip") != std::string::npos) search += ir;
  }
  md << fmt::format(
      "**Why the target is missed, and what would close it.** At the measured {:.1f} "
      "instructions per ns, "
      "10 ns/sample allows about {:.0f} instructions/sample; the loop executes {:.0f}, {:.0f} % "
      "too many "
      "(or it would need a higher IPC, which the dependent chain x -> x' of the affine map "
      "limits). Of "
      "those, the affine map of the step (the lines `x' = m.xx x + ...`, `v' = m.vx x + ...`) is "
      "{:.1f}, "
      "the running statistics {:.1f} and the non-finite guards {:.1f} instructions/sample: "
      "{:.0f} "
      "together, the work every sample needs. The other {:.0f} instructions/sample ({:.0f} %) "
      "are the "
      "friction logic around the map (first-order-hold input and relative acceleration at block "
      "ends, "
      "sign-change and dip tests, mode switches; the lines above).",
      ipc_ns, needed, per_step, 100.0 * (per_step / needed - 1.0), affine / profile.steps,
      statistics / profile.steps, guards / profile.steps, essential, rest / profile.steps,
      100.0 * rest / profile.self_total);
  if (search > 0.3 * profile.self_total && headline.events) {
    md << fmt::format(
        " The in-step event search (`Oscillator::slip`) alone is {:.0f} instructions/sample "
        "({:.0f} %), and it "
        "runs on every slipping step although only {:.1f} in 1000 steps hold an event. The lever "
        "is a "
        "whole-step fast path: advance a slipping step with the one precomputed map, show with a "
        "cheap "
        "bound that v_r cannot have changed sign inside it, and enter the dyadic search only "
        "when it may "
        "have. That would bring the loop towards the {:.0f} instructions of map, statistics and "
        "guards "
        "(about {:.0f} ns at the same IPC).",
        search / profile.steps, 100.0 * search / profile.self_total,
        1000.0 * *headline.events / static_cast<double>(headline.steps), essential,
        essential / ipc_ns);
  }
  md << "\n\n";
}

}  // namespace

void section_profile(std::ostream& md, const Results& results, const CallgrindDump& profile) {
  md << "## Where the time goes (callgrind)\n\n";
  if (profile.self_total <= 0.0 || profile.steps <= 0.0) {
    md << "No profile was recorded in this run.\n\n";
    return;
  }
  const Row* headline =
      results.find(kHeadlineScene, "stick-slip", "exact", "double", kHeadlineDtMs);
  const double per_step = profile.self_total / profile.steps;
  md << fmt::format(
      "The streaming loop of stick-slip / exact / double on {} at 1 ms over the whole scene "
      "({:.0f} steps) "
      "under callgrind: **{:.1f} instructions/sample**",
      kHeadlineScene, profile.steps, per_step);
  if (headline && headline->ns_median) {
    md << fmt::format(" in {} ns/sample, {:.1f} instructions per ns", ns(*headline->ns_median),
                      per_step / *headline->ns_median);
  }
  if (headline && headline->events) {
    md << fmt::format("; the scene has {:.1f} stick/slip events per 1000 steps",
                      1000.0 * *headline->events / static_cast<double>(headline->steps));
  }
  md << ".\n\nSelf cost per function (inlined code counts where it was inlined):\n\n";
  hot_functions(md, profile);
  hot_lines(md, profile);
  if (headline && headline->ns_median && *headline->ns_median > kTargetNsPerSample)
    target_miss(md, profile, *headline, per_step);
}

}  // namespace stickslip::tradeoff::report
