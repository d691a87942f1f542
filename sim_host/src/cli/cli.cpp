#include "stickslip/host/cli/cli.hpp"

#include <net/if.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <ostream>
#include <system_error>

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "stickslip/host/error.hpp"
#include "stop_signals.hpp"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif
#ifndef STICKSLIP_GIT_HASH
#define STICKSLIP_GIT_HASH "unknown"
#endif

namespace stickslip::host {
namespace {

// The subcommands, in the order --help and the unknown-subcommand message list them.
const struct Subcommand {
  const char* name;
  const char* description;
  std::unique_ptr<Command> (*make)();
} kSubcommands[] = {
    {"generate",
     "Write a synthetic cab-floor acceleration a_u(t) as CSV (t,a_u): the same file for the same "
     "options on every machine",
     make_generate_command},
    {"simulate",
     "Run the seat model over a recording; write t,a_u,x_r,v_r,a_x,f_f,stuck and print the "
     "statistics as a JSON line",
     make_simulate_command},
    {"demo",
     "Lorry recording -> signum and stick-slip on the reference seat -> which model the scene "
     "needs",
     make_demo_command},
    {"replay",
     "Stream a recording (CSV, or a candump .log) as CAN frames over a bus to the ECU node; write "
     "its samples as simulate does and print the statistics and the fault counters",
     make_replay_command},
    {"ecu",
     "The ECU node alone on a bus until --frames, --timeout, SIGINT or SIGTERM; prints its "
     "counters",
     make_ecu_command},
    {"record", "Write a CSV recording as a candump log of SeatInput frames (canplayer replays it)",
     make_record_command},
    {"play",
     "Send a recording's SeatInput frames on a bus at a multiple of real time, without a node; "
     "frames the bus refuses (e.g. while it is down) are counted, not retried",
     make_play_command},
    {"sweep",
     "T_ax and p against Den Hartog's K for recordings x models/integrators x damping values, on "
     "all cores; CSV out (one row per point, in a fixed order)",
     make_sweep_command},
    {"merge", "Join the shard files of a sweep into the CSV one unsharded run writes",
     make_merge_command},
    {"psd", "Welch PSD (Hann, 50 % overlap) of a recording's a_u: f_hz,psd in (m/s^2)^2/Hz",
     make_psd_command},
    {"harmonic-balance",
     "Den Hartog's harmonic-balance amplitude of x_r under a_u = A sin(2 pi f t) against the "
     "simulated steady state, over K (CSV)",
     make_harmonic_balance_command},
    {"advise",
     "For a recording and seat: a0u, K, p and T_ax of the cheap model against stick-slip, and the "
     "cheapest model/integrator whose T_ax error stays within the tolerance at its dt",
     make_advise_command},
    {"inspect",
     "What a recording holds (channels or CAN signals, units, rate, jitter, gaps, full-scale "
     "runs, NaNs) and the simulate command that reads it",
     make_inspect_command},
    {"fit",
     "Identify the seat (k, b, F_fk, F_fs, ...) from a rig recording t,a_u,a_x[,x_r] by least "
     "squares on the exact simulation; estimates with 95 % intervals, JSON line last",
     make_fit_command},
    {"closed-loop",
     "The seat with an actuator and a controller (skyhook, groundhook, active or semi-active) over "
     "a recording: the trace plus f_a, and passive vs controlled comfort and effort as a JSON "
     "line; --sweep-gain for the Pareto of comfort against effort",
     make_closed_loop_command},
    {"plant",
     "The seat under a recording on a CAN bus: sends its sensors every sample and holds the "
     "force of the controller's answer over the next step (with stickslip controller); trace and "
     "JSON as closed-loop's, with the bus's fault counters and pacing",
     make_plant_command},
    {"controller",
     "Observer, controller and actuator on a CAN bus: answers each sample of stickslip plant "
     "(or of a rig) with an ActuatorCommand frame",
     make_controller_command},
};

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::vector<std::string> subcommand_names() {
  std::vector<std::string> names;
  for (const Subcommand& subcommand : kSubcommands) names.emplace_back(subcommand.name);
  return names;
}

std::string subcommand_list() {
  return join_choices(subcommand_names(), ", ", " or ");
}

// CLI11 would only say "A subcommand is required" for a misspelt one, or for none.
void refuse_missing_or_unknown_subcommand(int argc, char** argv) {
  const std::string first = argc >= 2 ? argv[1] : "";
  if (first.empty()) {
    // An error rather than help on stdout: a script that lost its subcommand must not succeed.
    throw UsageError("a subcommand is required: " + subcommand_list() +
                     " (stickslip --help describes them; stickslip SUBCOMMAND --help its options)");
  }
  if (first[0] == '-') return;
  const std::vector<std::string> names = subcommand_names();
  if (std::find(names.begin(), names.end(), first) != names.end()) return;
  const std::string closest = closest_name(first, names);
  throw UsageError("unknown subcommand '" + first + "'" +
                   (closest.empty() ? "" : " (did you mean " + closest + "?)") + "; expected " +
                   subcommand_list() + " (see stickslip --help)");
}

// CLI11 reports a misspelt option as a missing required one, or as unexpected arguments in
// reverse order; this names it, with the closest option of the subcommand.
void refuse_unknown_options(const CLI::App& command, int argc, char** argv) {
  std::vector<std::string> names = {"--help"};
  for (const CLI::Option* option : command.get_options())
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  for (int i = 2; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--") return;
    if (argument.size() < 3 || argument.compare(0, 2, "--") != 0) continue;
    const std::string name = argument.substr(0, argument.find('='));
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    const std::string closest = closest_name(name, names);
    throw UsageError(command.get_name() + ": unknown option '" + name + "'" +
                     (closest.empty() ? "" : " (did you mean " + closest + "?)") +
                     "; see stickslip " + command.get_name() + " --help");
  }
}

// The options whose files a command reads, and those it writes.
constexpr const char* kInputOptions[] = {"--input", "--scene", "--dbc", "shards"};
constexpr const char* kOutputOptions[] = {"--output", "--stats", "--output-log", "--sample-index",
                                          "--plot"};

std::vector<std::pair<std::string, std::string>> given_files(const CLI::App& command,
                                                             const char* const* names,
                                                             std::size_t count) {
  std::vector<std::pair<std::string, std::string>> files;
  for (std::size_t i = 0; i < count; ++i) {
    const CLI::Option* option = command.get_option_no_throw(names[i]);
    if (option == nullptr || option->count() == 0) continue;
    for (const std::string& path : option->results()) files.emplace_back(names[i], path);
  }
  return files;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  if (std::filesystem::equivalent(a, b, error) && !error) return true;
  // An output not yet written: compare the paths it would have once links are resolved.
  const std::filesystem::path canonical_a = std::filesystem::weakly_canonical(a, error);
  if (error) return false;
  const std::filesystem::path canonical_b = std::filesystem::weakly_canonical(b, error);
  return !error && canonical_a == canonical_b;
}

// Before anything is read: an output that is (or, through links, resolves to) an input would
// replace the recording with what was computed from it, or two outputs would overwrite each
// other; --no-clobber refuses an output that exists.
void refuse_overlapping_files(const Options& command) {
  const auto inputs = given_files(command.app(), kInputOptions, std::size(kInputOptions));
  const auto outputs = given_files(command.app(), kOutputOptions, std::size(kOutputOptions));
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [output_option, output] = outputs[i];
    for (const auto& [input_option, input] : inputs) {
      if (same_file(output, input)) {
        throw UsageError(output_option + " " + output + " is the file " + input_option + " " +
                         input + " reads; write the result to another file");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (same_file(output, outputs[j].second)) {
        throw UsageError(output_option + " " + output + " and " + outputs[j].first + " " +
                         outputs[j].second + " are the same file; give each its own");
      }
    }
  }
  if (given(command, "--no-clobber")) {
    for (const auto& [option, output] : outputs) {
      std::error_code error;
      if (std::filesystem::exists(output, error)) {
        throw HostError(option + " " + output + ": exists, and --no-clobber keeps it");
      }
    }
  }
}

std::string version_text() {
  return std::string("stickslip ") + STICKSLIP_VERSION + " (git " + STICKSLIP_GIT_HASH + ")";
}

// One line, whatever the message holds.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

int parse_and_run(int argc, char** argv, std::ostream& out, std::ostream& err) {
  CLI::App app("stickslip: seat suspension with dry friction, simulated sample by sample",
               "stickslip");
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text(), "print the version and the build's git commit");
  app.footer(
      "Exit status: 0 success, 1 bad input data or failed file operation, 2 command-line error.");
  std::vector<std::unique_ptr<Command>> commands;
  std::deque<Options> options;  // one a subcommand, in the order of kSubcommands
  for (const Subcommand& subcommand : kSubcommands) {
    commands.push_back(subcommand.make());
    commands.back()->add_options(
        options.emplace_back(*app.add_subcommand(subcommand.name, subcommand.description)));
  }
  for (const Options& command : options) {
    if (command.app().get_option_no_throw("--output") != nullptr)
      command.app().add_flag("--no-clobber", "refuse to replace an existing output file");
  }
  refuse_missing_or_unknown_subcommand(argc, argv);
  for (const Options& command : options)
    if (command.app().get_name() == argv[1]) refuse_unknown_options(command.app(), argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForVersion& version) {
    out << version.what() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) {  // --help
      out << app.help();
      return kExitOk;
    }
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitUsage;
  }
  for (std::size_t i = 0; i < commands.size(); ++i) {
    if (!options[i].app().parsed()) continue;
    refuse_overlapping_files(options[i]);
    try {
      return commands[i]->run(options[i], out, err);
    } catch (const ConfigurationError& error) {
      // Parameters from the command line are a usage error; from a scene file, bad data.
      if (given(options[i], "--scene")) throw;
      throw UsageError(error.what());
    }
  }
  return kExitUsage;  // require_subcommand(1) leaves no other case
}

}  // namespace

std::string join_choices(const std::vector<std::string>& choices, const char* separator,
                         const char* last_separator) {
  std::string text;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) text += i + 1 == choices.size() ? last_separator : separator;
    text += choices[i];
  }
  return text;
}

std::string closest_name(const std::string& typed, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, typed.size() / 3) + 1;
  for (const std::string& name : names) {
    const std::size_t distance = edit_distance(typed, name);
    if (distance < best_distance) {
      best_distance = distance;
      best = name;
    }
  }
  return best;
}

std::string did_you_mean(const std::string& typed, const std::vector<std::string>& names) {
  const std::string closest = closest_name(typed, names);
  return closest.empty() ? std::string() : "; did you mean " + closest + "?";
}

void check_bus_name(const char* option, const std::string& bus) {
  if (bus == "loopback" || ::if_nametoindex(bus.c_str()) != 0) return;
  if (closest_name(bus, {"loopback"}).empty()) return;
  throw UsageError(std::string(option) + " " + bus +
                   ": no such bus (did you mean loopback? otherwise a CAN interface of this "
                   "machine, such as vcan0)");
}

bool stderr_is_terminal(const std::ostream& err) {
  return &err == &std::cerr && ::isatty(2) == 1;
}

std::function<void(std::uint64_t, std::uint64_t)> make_frame_progress(std::ostream& err,
                                                                      const char* what,
                                                                      bool enabled,
                                                                      std::string waiting) {
  if (!enabled && waiting.empty()) return nullptr;
  using Clock = std::chrono::steady_clock;
  auto next = std::make_shared<Clock::time_point>(Clock::now() + std::chrono::seconds(2));
  auto calls = std::make_shared<std::uint64_t>(0);
  return [&err, what, enabled, waiting, next, calls](std::uint64_t done, std::uint64_t total) {
    if ((*calls)++ == 0 && !waiting.empty()) err << waiting << "\n" << std::flush;
    // The clock only every 256 frames: a fast replay calls this a million times a second.
    if (!enabled || (*calls & 0xFF) != 0) return;
    const Clock::time_point now = Clock::now();
    if (now < *next) return;
    *next = now + std::chrono::seconds(1);
    if (total > 0) {
      err << what << ": " << done << "/" << total << " frames (" << 100 * done / total << " %)\n";
    } else {
      err << what << ": " << done << " frames\n";
    }
    err.flush();
  };
}

int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err) {
  try {
    return parse_and_run(argc, argv, out, err);
  } catch (const UsageError& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitUsage;
  } catch (const HostError& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    err << "stickslip: out of memory\n";
    return kExitFailure;
  } catch (const std::exception& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitFailure;
  } catch (...) {
    err << "stickslip: unexpected error\n";
    return kExitFailure;
  }
}

int run_cli_process(int argc, char** argv) {
  const InterruptCleanup cleanup;
  return run_cli(argc, argv, std::cout, std::cerr);
}

int run_cli(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  std::vector<std::string> storage;
  storage.reserve(arguments.size() + 1);
  storage.emplace_back("stickslip");
  storage.insert(storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& argument : storage) argv.push_back(argument.data());
  argv.push_back(nullptr);
  return run_cli(static_cast<int>(storage.size()), argv.data(), out, err);
}

}  // namespace stickslip::host
