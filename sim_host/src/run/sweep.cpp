#include "stickslip/host/run/sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <ostream>
#include <thread>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/metrics/batch_statistics.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/batch.hpp"
#include "stickslip/models/dispatch.hpp"

namespace stickslip::host {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kBatchLanes = 8;

struct Recording {
  std::string name;
  SampledSignal signal;  // --gaps split: the parts end to end
  double a0u = 0.0;      // RMS as RunningStatistics measures it
  // --gaps split: the first sample of each part after the first; each part runs from rest, and
  // the statistics sum over all parts (RMS by samples, p by steps, as simulate reports them).
  std::vector<std::size_t> part_starts;
  bool part_starts_at(std::size_t n, std::size_t& next) const noexcept {
    if (next < part_starts.size() && part_starts[next] == n) return ++next, true;
    return false;
  }
};

struct Point {
  std::uint64_t index = 0;
  std::size_t input = 0;
  SweepMethod method;
  double damping = 0.0;
  double k_target = 0.0;
  double friction_n = 0.0;
  double scale = 1.0;
  OscillatorParams params;
};

double rms_of(const std::vector<double>& a_u) {
  RunningStatistics<double> statistics;
  statistics.reset();
  for (double value : a_u) statistics.add_sample(value, 0.0);
  return statistics.rms_u();
}

std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
  return hash;
}
std::uint64_t hash_double(std::uint64_t hash, double value) {
  return fnv1a(hash, &value, sizeof value);
}
std::uint64_t hash_text(std::uint64_t hash, const std::string& text) {
  return fnv1a(hash, text.c_str(), text.size() + 1);
}

void validate(const SweepRequest& r) {
  if (r.inputs.empty()) throw UsageError("--input: at least one recording is needed");
  if (r.methods.empty()) throw UsageError("--method: at least one model[:integrator] is needed");
  if (r.damping_ns_per_m.empty()) throw UsageError("--damping: at least one value is needed");
  if (r.k_values.empty()) throw UsageError("--k: at least one K value is needed");
  for (const std::string& input : r.inputs) {
    if (input.find_first_of(",\n\r\"") != std::string::npos)
      throw UsageError("--input: '" + input +
                       "': names with , \" or line breaks cannot go in the CSV");
  }
  for (double b : r.damping_ns_per_m) {
    if (!std::isfinite(b) || b < 0.0)
      throw UsageError(fmt::format("--damping: must be >= 0, got {}", b));
  }
  for (double k : r.k_values) {
    const bool ok = std::isfinite(k) && (r.vary == SweepVariable::friction ? k >= 0.0 : k > 0.0);
    if (!ok) {
      throw UsageError(fmt::format("--k: must be {} and finite, got {}",
                                   r.vary == SweepVariable::friction ? ">= 0" : "> 0", k));
    }
  }
  if (!std::isfinite(r.mass_kg) || !(r.mass_kg > 0.0))
    throw UsageError(fmt::format("--mass: must be > 0, got {}", r.mass_kg));
  if (!std::isfinite(r.friction_n) || !(r.friction_n > 0.0))
    throw UsageError(fmt::format("--ffk: must be > 0, got {}", r.friction_n));
  if (!std::isfinite(r.static_friction_ratio) || !(r.static_friction_ratio >= 1.0))
    throw UsageError(fmt::format("--ffs-ratio: must be >= 1, got {}", r.static_friction_ratio));
  if (r.shard_count < 1 || r.shard_index < 1 || r.shard_index > r.shard_count)
    throw UsageError(
        fmt::format("--shard: need 1 <= I <= N, got {}/{}", r.shard_index, r.shard_count));
}

std::vector<Recording> load(const SweepRequest& r, std::vector<std::string>& notes) {
  std::vector<Recording> recordings;
  for (const std::string& path : r.inputs) {
    Recording recording;
    recording.name = path;
    LoadedRecording loaded = read_recording(path, r.recording);
    const RecordingReport& report = loaded.report;
    recording.signal = std::move(loaded.segments.front());
    for (std::size_t i = 1; i < loaded.segments.size(); ++i) {
      const SampledSignal& part = loaded.segments[i];
      recording.part_starts.push_back(recording.signal.a_u_m_per_s2.size());
      recording.signal.t_s.insert(recording.signal.t_s.end(), part.t_s.begin(), part.t_s.end());
      recording.signal.a_u_m_per_s2.insert(recording.signal.a_u_m_per_s2.end(),
                                           part.a_u_m_per_s2.begin(), part.a_u_m_per_s2.end());
    }
    const std::string note = describe_recording(path, report);
    if (!note.empty()) notes.push_back(note);
    recording.a0u = rms_of(recording.signal.a_u_m_per_s2);
    if (!(recording.a0u > 0.0)) throw HostError(path + ": a_u is zero throughout; K is undefined");
    recordings.push_back(std::move(recording));
  }
  return recordings;
}

// Every point of the whole sweep, in order, and the hash of their definitions.
std::vector<Point> all_points(const SweepRequest& r, const std::vector<Recording>& recordings,
                              std::uint64_t& config_hash) {
  std::vector<Point> points;
  std::uint64_t hash = 14695981039346656037ull;
  hash = hash_double(hash, r.mass_kg);
  hash = hash_double(hash, r.stiffness_n_per_m);
  hash = hash_double(hash, r.static_friction_ratio);
  hash = hash_double(hash, r.vary == SweepVariable::friction ? 0.0 : r.friction_n);
  for (std::size_t input = 0; input < recordings.size(); ++input) {
    const Recording& recording = recordings[input];
    hash = hash_text(hash, recording.name);
    hash = hash_double(hash, recording.a0u);
    hash = hash_double(hash, static_cast<double>(recording.signal.a_u_m_per_s2.size()));
    // Split parts run otherwise than one signal: shards of the two must not merge.
    if (!recording.part_starts.empty())
      hash = hash_double(hash, static_cast<double>(recording.part_starts.size()));
    hash = hash_double(hash, recording.signal.dt_s);
    for (double b : r.damping_ns_per_m) {
      for (const SweepMethod& method : r.methods) {
        for (double k_target : r.k_values) {
          Point p;
          p.index = points.size();
          p.input = input;
          p.method = method;
          p.damping = b;
          p.k_target = k_target;
          // K = 4 F / (pi sqrt(2) m a0u): solve for F at the recording's a0u, or for the a0u
          // (hence the scale of the recording) at the fixed F.
          const double den = kPi * std::sqrt(2.0) * r.mass_kg / 4.0;
          if (r.vary == SweepVariable::friction) {
            p.friction_n = k_target * den * recording.a0u;
          } else {
            p.friction_n = r.friction_n;
            p.scale = r.friction_n / (den * k_target) / recording.a0u;
          }
          OscillatorParams& q = p.params;
          q.mass_kg = r.mass_kg;
          q.stiffness_n_per_m = r.stiffness_n_per_m;
          q.damping_ns_per_m = b;
          q.kinetic_friction_n = p.friction_n;
          q.static_friction_n = p.friction_n * r.static_friction_ratio;
          q.model = method.model;
          q.integrator = method.integrator;
          q.dt_s = recording.signal.dt_s;
          hash = hash_text(hash, sweep_method_name(method));
          hash = hash_double(hash, b);
          hash = hash_double(hash, k_target);
          points.push_back(p);
        }
      }
    }
  }
  config_hash = hash;
  return points;
}

SweepRow row_for(const Point& p, const Recording& recording, const RunningStatistics<double>& s,
                 std::uint64_t events) {
  SweepRow row;
  row.point = p.index;
  row.input = recording.name;
  row.method = sweep_method_name(p.method);
  row.damping_ns_per_m = p.damping;
  row.k_target = p.k_target;
  row.friction_n = p.friction_n;
  row.scale = p.scale;
  row.a0u = s.rms_u();
  row.k = den_hartog_factor(p.friction_n, p.params.mass_kg, row.a0u);
  row.transmissibility = s.transmissibility();
  row.stick_probability = s.stick_probability();
  row.rms_x = s.rms_x();
  row.events = events;
  return row;
}

// One point by its own oscillator (the loop of simulate_signal, without the trace).
SweepRow run_single(const Point& p, const Recording& recording) {
  const std::vector<double>& input = recording.signal.a_u_m_per_s2;
  return with_oscillator<double>(p.params, [&](auto& oscillator) {
    const ConfigResult configured = oscillator.configure(p.params);
    if (!configured.ok()) throw HostError(configured.message.c_str());
    RunningStatistics<double> statistics;
    statistics.reset();
    std::uint64_t events = 0;
    const double scale = p.scale;
    oscillator.reset(0.0, 0.0, scale * input[0]);
    statistics.add_sample(scale * input[0], oscillator.current().a_x_m_per_s2);
    std::size_t next_part = 0;
    for (std::size_t n = 1; n < input.size(); ++n) {
      const double a_u = scale * input[n];
      if (recording.part_starts_at(n, next_part)) {  // a new part: from rest, no step across
        oscillator.reset(0.0, 0.0, a_u);
        statistics.add_sample(a_u, oscillator.current().a_x_m_per_s2);
        continue;
      }
      const StepOutput<double> out = oscillator.step(a_u);
      statistics.add_sample(a_u, out.a_x_m_per_s2);
      statistics.add_step(out.stuck_fraction);
      events += out.events;
    }
    return row_for(p, recording, statistics, events);
  });
}

// Up to 8 stick-slip points of one recording, stepped together (lanes beyond `count` repeat
// lane 0 and are ignored).
void run_batch(const Point* const* points, std::size_t count, const Recording& recording,
               SweepRow* rows) {
  using Batch = StickSlipBatch<double, kBatchLanes>;
  auto batch = std::make_unique<Batch>();
  auto statistics = std::make_unique<BatchStatistics<double, kBatchLanes>>();
  const std::vector<double>& input = recording.signal.a_u_m_per_s2;
  double scale[kBatchLanes], a_u[kBatchLanes], a_x[kBatchLanes];
  std::uint64_t events[kBatchLanes] = {};
  for (std::size_t lane = 0; lane < kBatchLanes; ++lane) {
    const Point& p = *points[lane < count ? lane : 0];
    const ConfigResult configured = batch->configure(lane, p.params);
    if (!configured.ok()) throw HostError(configured.message.c_str());
    scale[lane] = p.scale;
    a_u[lane] = scale[lane] * input[0];
    batch->reset(lane, 0.0, 0.0, a_u[lane]);
    a_x[lane] = batch->lane(lane).current().a_x_m_per_s2;
  }
  statistics->reset();
  statistics->add_sample(a_u, a_x);
  std::size_t next_part = 0;
  for (std::size_t n = 1; n < input.size(); ++n) {
    for (std::size_t lane = 0; lane < kBatchLanes; ++lane) a_u[lane] = scale[lane] * input[n];
    if (recording.part_starts_at(n, next_part)) {  // a new part: from rest, no step across
      for (std::size_t lane = 0; lane < kBatchLanes; ++lane) {
        batch->reset(lane, 0.0, 0.0, a_u[lane]);
        a_x[lane] = batch->lane(lane).current().a_x_m_per_s2;
      }
      statistics->add_sample(a_u, a_x);
      continue;
    }
    batch->step(a_u);
    statistics->add_sample(a_u, batch->a_x_array());
    statistics->add_step(batch->stuck_fraction_array());
    for (std::size_t lane = 0; lane < kBatchLanes; ++lane) events[lane] += batch->events(lane);
  }
  for (std::size_t lane = 0; lane < count; ++lane)
    rows[lane] = row_for(*points[lane], recording, statistics->lane(lane), events[lane]);
}

// Tasks: a single point, or a batch of stick-slip points of the same recording.
struct Task {
  std::size_t first = 0;  // into the shard's point list
  std::size_t count = 1;
  bool batch = false;
};

std::vector<Task> plan_tasks(const std::vector<const Point*>& points, bool use_batch) {
  std::vector<Task> tasks;
  for (std::size_t i = 0; i < points.size();) {
    const Point& p = *points[i];
    if (use_batch && p.method.model == FrictionModel::stick_slip) {
      std::size_t j = i + 1;
      while (j < points.size() && j - i < kBatchLanes &&
             points[j]->method.model == FrictionModel::stick_slip && points[j]->input == p.input) {
        ++j;
      }
      if (j - i >= 2) {
        tasks.push_back({i, j - i, true});
        i = j;
        continue;
      }
    }
    tasks.push_back({i, 1, false});
    ++i;
  }
  return tasks;
}

void check_configurations(const std::vector<const Point*>& points,
                          const std::vector<Recording>& recordings) {
  for (const Point* p : points) {
    with_oscillator<double>(p->params, [&](auto& oscillator) {
      const ConfigResult configured = oscillator.configure(p->params);
      if (!configured.ok()) {
        throw UsageError(fmt::format("point {} ({}, {}, b = {}, K = {}): {}", p->index,
                                     recordings[p->input].name, sweep_method_name(p->method),
                                     p->damping, p->k_target, configured.message.c_str()));
      }
      return 0;
    });
  }
}

struct Prepared {
  std::vector<Recording> recordings;
  std::vector<Point> points;
  std::vector<const Point*> shard;
  std::uint64_t config_hash = 0;
  std::vector<std::string> recording_notes;
};

Prepared prepare(const SweepRequest& request) {
  validate(request);
  Prepared prepared;
  prepared.recordings = load(request, prepared.recording_notes);
  prepared.points = all_points(request, prepared.recordings, prepared.config_hash);
  for (const Point& p : prepared.points) {
    if (p.index % request.shard_count == request.shard_index - 1) prepared.shard.push_back(&p);
  }
  check_configurations(prepared.shard, prepared.recordings);
  return prepared;
}

std::vector<SweepRow> execute(const SweepRequest& request, const Prepared& prepared,
                              SweepSummary& summary, const SweepProgress& progress) {
  const std::vector<const Point*>& points = prepared.shard;
  const std::vector<Task> tasks = plan_tasks(points, request.batch);
  std::vector<SweepRow> rows(points.size());
  unsigned threads = request.threads != 0 ? request.threads : std::thread::hardware_concurrency();
  if (threads == 0) threads = 1;
  threads =
      static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(tasks.size(), 1)));

  std::atomic<std::size_t> next_task{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;  // guards progress, done, first_error
  std::uint64_t done = 0;
  std::exception_ptr first_error;
  std::size_t first_error_task = tasks.size();
  const auto start = std::chrono::steady_clock::now();
  const auto worker = [&] {
    for (;;) {
      const std::size_t t = next_task.fetch_add(1);
      if (t >= tasks.size() || failed.load()) return;
      const Task& task = tasks[t];
      try {
        if (task.batch) {
          run_batch(&points[task.first], task.count, prepared.recordings[points[task.first]->input],
                    &rows[task.first]);
        } else {
          const Point& p = *points[task.first];
          rows[task.first] = run_single(p, prepared.recordings[p.input]);
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (t < first_error_task) {
          first_error_task = t;
          first_error = std::current_exception();
        }
        failed.store(true);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      done += task.count;
      if (progress) progress(done, points.size());
    }
  };
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  if (first_error) std::rethrow_exception(first_error);

  summary.points_total = prepared.points.size();
  summary.points_run = points.size();
  summary.samples = 0;
  for (const Point* p : points)
    summary.samples += prepared.recordings[p->input].signal.a_u_m_per_s2.size() - 1 -
                       prepared.recordings[p->input].part_starts.size();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.threads = threads;
  return rows;
}

void write_rows(CsvWriter& writer, const std::vector<SweepRow>& rows, double ratio) {
  writer.text(kSweepHeader);
  writer.text("\n");
  for (const SweepRow& row : rows) {
    const auto colon = row.method.find(':');
    writer.text(std::to_string(row.point));
    writer.separator();
    writer.text(row.input);
    writer.separator();
    writer.text(row.method.substr(0, colon));
    writer.separator();
    writer.text(row.method.substr(colon + 1));
    for (double value :
         {row.damping_ns_per_m, row.k_target, row.friction_n, row.friction_n * ratio, row.scale,
          row.a0u, row.k, row.transmissibility, row.stick_probability, row.rms_x}) {
      writer.separator();
      writer.number(value);
    }
    writer.separator();
    writer.text(std::to_string(row.events));
    writer.end_row();
  }
}

}  // namespace

SweepMethod parse_sweep_method(const std::string& text) {
  SweepMethod method;
  const auto colon = text.find(':');
  const std::string model = text.substr(0, colon);
  if (!parse_model(model.c_str(), method.model)) {
    throw UsageError("--method: unknown model '" + model + "' in '" + text +
                     "' (expected linear, signum, smooth, stick-slip or stribeck)");
  }
  method.integrator = default_integrator(method.model);
  if (colon != std::string::npos) {
    const std::string integrator = text.substr(colon + 1);
    if (!parse_integrator(integrator.c_str(), method.integrator)) {
      throw UsageError("--method: unknown integrator '" + integrator + "' in '" + text +
                       "' (expected euler, symplectic, rk4 or exact)");
    }
  }
  return method;
}

std::string sweep_method_name(const SweepMethod& method) {
  return std::string(model_name(method.model)) + ":" + integrator_name(method.integrator);
}

std::vector<SweepRow> compute_sweep(const SweepRequest& request, SweepSummary* summary,
                                    const SweepProgress& progress) {
  const Prepared prepared = prepare(request);
  // The total before the first point ends: an interruption can then say "0 of N points done".
  if (progress) progress(0, prepared.shard.size());
  SweepSummary local;
  std::vector<SweepRow> rows = execute(request, prepared, local, progress);
  if (summary) *summary = local;
  return rows;
}

SweepSummary run_sweep(const SweepRequest& request, const std::string& output_path,
                       const SweepProgress& progress) {
  const Prepared prepared = prepare(request);
  if (progress) progress(0, prepared.shard.size());  // as in compute_sweep
  AtomicOutputFile file(output_path);                // a bad path fails before the work
  SweepSummary summary;
  summary.recording_notes = prepared.recording_notes;
  const std::vector<SweepRow> rows = execute(request, prepared, summary, progress);
  CsvWriter writer(file);
  if (request.shard_count > 1 || request.shard_file) {
    writer.text(fmt::format("{}{}/{} points {} config {:016x}\n", kShardTag, request.shard_index,
                            request.shard_count, prepared.points.size(), prepared.config_hash));
  }
  write_rows(writer, rows, request.static_friction_ratio);
  writer.flush();
  file.commit();
  return summary;
}

SweepProgress make_progress_reporter(std::ostream& err, bool terminal) {
  auto last_decile = std::make_shared<std::uint64_t>(0);
  return [&err, terminal, last_decile](std::uint64_t done, std::uint64_t total) {
    if (total == 0) return;
    if (terminal) {
      constexpr int kWidth = 40;
      const int filled = static_cast<int>(kWidth * done / total);
      err << '\r' << "sweep [" << std::string(static_cast<std::size_t>(filled), '#')
          << std::string(static_cast<std::size_t>(kWidth - filled), ' ') << "] " << done << "/"
          << total << (done == total ? "\n" : "") << std::flush;
      return;
    }
    const std::uint64_t decile = 10 * done / total;
    if (decile > *last_decile || done == total) {
      *last_decile = decile;
      err << "sweep: " << done << "/" << total << " points (" << 100 * done / total << " %)\n";
    }
  };
}

}  // namespace stickslip::host
