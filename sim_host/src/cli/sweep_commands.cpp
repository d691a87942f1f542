// stickslip sweep and merge: K sweeps on a thread pool, and the join of their shards (sweep.hpp).
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <ostream>

#include "command.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/sweep.hpp"
#include "stop_signals.hpp"

namespace stickslip::host {
namespace {

std::vector<double> k_values_from_range(const std::string& text) {
  double low = 0.0, high = 0.0;
  int count = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf:%d%c", &low, &high, &count, &tail) != 3 || count < 1 ||
      !(high >= low) || (count == 1 && high != low)) {
    throw UsageError("--k-range: expected MIN:MAX:COUNT with MIN <= MAX, COUNT >= 1, got '" + text +
                     "'");
  }
  std::vector<double> values;
  for (int i = 0; i < count; ++i)
    values.push_back(count == 1 ? low : low + (high - low) * i / (count - 1));
  return values;
}

void parse_shard(const std::string& text, SweepRequest& request) {
  unsigned index = 0, count = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%u/%u%c", &index, &count, &tail) != 2 || count < 1 || index < 1 ||
      index > count) {
    throw UsageError("--shard: expected I/N with 1 <= I <= N, got '" + text + "'");
  }
  request.shard_index = index;
  request.shard_count = count;
}

class SweepCommand : public Command {
 public:
  void add_options(Options& sweep) override {
    sweep
        .add_option("--input", request_.inputs,
                    "recording (CSV t,a_u, .mat, a logger's text, a CAN log with --dbc); repeat "
                    "for more")
        ->required();
    sweep
        .add_option("--method", methods_,
                    "MODEL[:INTEGRATOR], repeat or comma-separate (default signum:euler and "
                    "stick-slip:exact)")
        ->delimiter(',');
    sweep.add_option("--damping", request_.damping_ns_per_m, "b values, N s/m (comma-separated)")
        ->delimiter(',')
        ->required();
    sweep.add_option("--k", request_.k_values, "K values (comma-separated)")->delimiter(',');
    sweep.add_option("--k-range", k_range_, "MIN:MAX:COUNT, evenly spaced K values");
    sweep
        .add_option("--vary", vary_,
                    "friction (F_fk from K at the recording's a0u) | excitation (the recording "
                    "scaled to the a0u of K at --ffk)")
        ->capture_default_str();
    sweep.add_option("--ffk", request_.friction_n, "F_fk, N (--vary excitation)")
        ->capture_default_str();
    sweep.add_option("--ffs-ratio", request_.static_friction_ratio, "F_fs / F_fk")
        ->capture_default_str();
    add_seat_options(sweep, request_.mass_kg, request_.stiffness_n_per_m);
    sweep.add_option("--threads", request_.threads, "worker threads (default: all cores)");
    sweep.add_option(
        "--shard", shard_,
        "I/N: run only the points with index % N == I - 1 (join with `stickslip merge`)");
    sweep.add_flag("--no-batch", no_batch_, "step every point alone (same results, slower)");
    sweep.add_flag("--quiet", quiet_, "no progress on stderr");
    sweep.add_option("--output", output_, "CSV file to write")->required();
    recording_.add_to(sweep);
  }

  int run(Options&, std::ostream& out, std::ostream& err) override {
    const SweepRequest request = resolve();
    const SweepProgress report =
        quiet_ ? SweepProgress() : make_progress_reporter(err, stderr_is_terminal(err));
    // The counts also go where an interruption's one line reads them.
    const SweepProgress progress = [&report](std::uint64_t done, std::uint64_t total) {
      interrupt_points_total = total;
      interrupt_points_done = done;
      if (report) report(done, total);
    };
    const SweepSummary s = run_sweep(request, output_, progress);
    for (const std::string& note : s.recording_notes) err << "stickslip: " << note << "\n";
    out << fmt::format(
        "wrote {}: {} of {} points, {} steps in {:.3f} s on {} thread{} ({:.1f} Msteps/s)\n",
        output_, s.points_run, s.points_total, s.samples, s.seconds, s.threads,
        s.threads == 1 ? "" : "s",
        s.seconds > 0.0 ? static_cast<double>(s.samples) / s.seconds * 1e-6 : 0.0);
    return kExitOk;
  }

 private:
  SweepRequest resolve() const {
    SweepRequest request = request_;
    for (const std::string& method : methods_)
      request.methods.push_back(parse_sweep_method(method));
    if (!k_range_.empty() && !request.k_values.empty()) {
      throw UsageError("--k and --k-range: give one of them (both would sweep the union)");
    }
    if (!k_range_.empty()) {
      const std::vector<double> range = k_values_from_range(k_range_);
      request.k_values.insert(request.k_values.end(), range.begin(), range.end());
    }
    if (vary_ == "friction") {
      request.vary = SweepVariable::friction;
    } else if (vary_ == "excitation") {
      request.vary = SweepVariable::excitation;
    } else {
      throw UsageError("--vary: expected friction or excitation, got '" + vary_ + "'");
    }
    if (!shard_.empty()) {
      parse_shard(shard_, request);
      request.shard_file = true;
    }
    request.batch = !no_batch_;
    request.recording = recording_.resolve();
    return request;
  }

  SweepRequest request_;
  std::vector<std::string> methods_ = {"signum:euler", "stick-slip:exact"};
  std::string k_range_;  // "min:max:count"
  std::string vary_ = "friction";
  std::string shard_;
  std::string output_;
  RecordingOptionGroup recording_;
  bool no_batch_ = false;
  bool quiet_ = false;
};

class MergeCommand : public Command {
 public:
  void add_options(Options& merge) override {
    merge.add_option("shards", inputs_, "shard CSV files (any order)")->required();
    merge.add_option("--output", output_, "CSV file to write")->required();
  }

  int run(Options&, std::ostream& out, std::ostream&) override {
    merge_sweep_shards(inputs_, output_);
    out << fmt::format("wrote {} from {} shards\n", output_, inputs_.size());
    return kExitOk;
  }

 private:
  std::vector<std::string> inputs_;
  std::string output_;
};

}  // namespace

std::unique_ptr<Command> make_sweep_command() {
  return std::make_unique<SweepCommand>();
}

std::unique_ptr<Command> make_merge_command() {
  return std::make_unique<MergeCommand>();
}

}  // namespace stickslip::host
