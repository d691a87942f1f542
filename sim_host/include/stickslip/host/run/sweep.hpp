// K sweeps: T_ax and p against Den Hartog's K = 4 F_fk / (pi sqrt(2) m a0u) for a set of
// recordings, friction models/integrators and damping values, on all cores.
//
// A sweep is a list of points in a fixed order (input, damping, method, K: the last varies
// fastest). Each point is one simulation of a whole recording, either with F_fk chosen for the K
// at the recording's own a0u (vary friction), or with the recording scaled to the a0u that gives
// the K at a fixed F_fk (vary excitation). F_fs = ratio * F_fk. Results are written in point order
// whatever the number of threads, and a shard (I/N: the points with index % N == I - 1) writes
// exactly the rows a full run writes for those points, so merge_sweep_shards() rebuilds the full
// file byte for byte. Stick-slip points with the same input are stepped 8 at a time in the SoA
// batch (models/batch.hpp), whose lanes equal a single oscillator bit for bit.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

enum class SweepVariable : std::uint8_t { friction, excitation };

struct SweepMethod {
  FrictionModel model = FrictionModel::stick_slip;
  Integrator integrator = Integrator::exact;
};

// "stick-slip:exact", "signum:euler", "signum" (default integrator); throws UsageError.
SweepMethod parse_sweep_method(const std::string& text);
std::string sweep_method_name(const SweepMethod& method);

struct SweepRequest {
  std::vector<std::string> inputs;  // recordings, read as `recording` says
  RecordingOptions recording;
  std::vector<SweepMethod> methods;
  std::vector<double> damping_ns_per_m;
  std::vector<double> k_values;
  SweepVariable vary = SweepVariable::friction;
  double mass_kg = 88.4;
  double stiffness_n_per_m = 11500.0;
  double friction_n = 45.0;            // F_fk when varying the excitation
  double static_friction_ratio = 1.0;  // F_fs / F_fk >= 1
  unsigned threads = 0;                // 0: std::thread::hardware_concurrency()
  unsigned shard_index = 1;            // 1-based
  unsigned shard_count = 1;
  bool shard_file = false;  // write the shard line even for 1/1 (`--shard` given)
  bool batch = true;        // stick-slip points through StickSlipBatch
};

// One row of the output CSV.
struct SweepRow {
  std::uint64_t point = 0;
  std::string input;
  std::string method;
  double damping_ns_per_m = 0.0;
  double k_target = 0.0;
  double friction_n = 0.0;  // F_fk used
  double scale = 1.0;       // factor applied to the recording
  double a0u = 0.0;         // measured RMS of the (scaled) input
  double k = 0.0;           // K from F_fk, m and a0u
  double transmissibility = 0.0;
  double stick_probability = 0.0;
  double rms_x = 0.0;
  std::uint64_t events = 0;
};

inline constexpr const char* kSweepHeader =
    "point,input,model,integrator,b_ns_per_m,K_target,ffk_n,ffs_n,scale,a0u,K,T_ax,p,rms_x,events";

// "# stickslip sweep shard I/N points P config HHHHHHHHHHHHHHHH": the first line of a shard file
// (absent from an unsharded run). The config hash covers every point's definition.
inline constexpr const char* kShardTag = "# stickslip sweep shard ";

// Progress: called from one thread at a time with (points done, points in this run).
using SweepProgress = std::function<void(std::uint64_t, std::uint64_t)>;

struct SweepSummary {
  std::uint64_t points_total = 0;  // in the whole sweep
  std::uint64_t points_run = 0;    // in this shard
  std::uint64_t samples = 0;       // simulated steps, all points of this run
  double seconds = 0.0;
  unsigned threads = 0;
  std::vector<std::string> recording_notes;  // what reading did to each input (if anything)
};

// Validates (UsageError naming the option), loads the inputs, runs this shard's points on the
// thread pool and writes the CSV to `output_path` atomically.
SweepSummary run_sweep(const SweepRequest& request, const std::string& output_path,
                       const SweepProgress& progress = nullptr);

// The rows alone (no file), in point order: for tests and other commands.
std::vector<SweepRow> compute_sweep(const SweepRequest& request, SweepSummary* summary = nullptr,
                                    const SweepProgress& progress = nullptr);

// Joins shard files into the CSV an unsharded run writes. Checks that every file is a shard of
// the same sweep (same config hash, same N), that each shard appears once and every point once,
// and that nothing is missing; throws HostError naming the file and problem otherwise.
void merge_sweep_shards(const std::vector<std::string>& shard_paths,
                        const std::string& output_path);

// A progress reporter writing to `err`: a redrawn bar when `terminal`, else a plain line at
// every 10 %.
SweepProgress make_progress_reporter(std::ostream& err, bool terminal);

}  // namespace stickslip::host
