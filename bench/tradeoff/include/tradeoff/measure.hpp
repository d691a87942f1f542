// One combination of the library measured: configure (a refusal is a result, not an error), the
// untimed trace for the comparison, the timed streaming loop, the errors against the reference,
// and the instruction count under callgrind.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "tradeoff/combinations.hpp"
#include "tradeoff/reference.hpp"
#include "tradeoff/stream_loop.hpp"

namespace stickslip::tradeoff {

// The input of one dt in both scalar types.
struct SampledInput {
  std::vector<double> as_double;
  std::vector<float> as_float;
};

struct Outcome {
  std::string status = "ok";  // "ok", "refused: <parameter>", "unstable"
  std::string note;           // configure's message, or why the run counts as unstable
  RunTrace trace;
  std::optional<TimingResult> timing;  // only for runs that are ok
};

// Errors of a trace against a reference (both one row per input sample).
struct Errors {
  double transmissibility_rel = 0.0;        // |T_ax - T_ax,ref| / T_ax,ref
  std::optional<double> stick_prob_abs;     // |p - p_ref|, for models with a stuck state
  double a_x_rms = 0.0, a_x_rms_rel = 0.0;  // RMS(a_x - a_x,ref), and over RMS(a_x,ref)
  double x_r_rms = 0.0, x_r_rms_rel = 0.0;
};
Errors compare(const RunTrace& trace, const Reference& reference);

// A run that stays finite but leaves any physical range (10x the reference's largest |x_r| plus
// 1 m, or 100x its RMS a_x plus 10 m/s^2) has blown up; the reason, or empty.
std::string blow_up_reason(const RunTrace& trace, const Reference& reference);

// Configures, traces and (unless the run is refused or blows up) times the combination.
Outcome run_library(const OscillatorParams& params, host::ScalarType scalar,
                    const SampledInput& input, const Reference& physics, const Timing& timing);

// "refused: <parameter>" from configure()'s message ("dt_s: ..." names the parameter first).
std::string refused_status(const std::string& message);

// True when running under valgrind (the callgrind client requests then count).
bool running_on_valgrind() noexcept;
// Runs the streaming loop once over the first steps + 1 samples with callgrind collecting (zeroed
// before, toggled around the loop) and dumps the counts as "<name>#<steps>". False if configure()
// refuses.
bool count_library(const OscillatorParams& params, host::ScalarType scalar,
                   const SampledInput& input, std::size_t steps, const std::string& name);

// Build facts compiled in (compiler, flags, build type).
const char* build_compiler() noexcept;
const char* build_flags() noexcept;
const char* build_type() noexcept;

}  // namespace stickslip::tradeoff
