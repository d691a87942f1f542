#include "stickslip/host/cli/cli.hpp"

#include <exception>
#include <new>
#include <ostream>

#include "command.hpp"
#include "stickslip/host/error.hpp"

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
    {"ecu", "The ECU node alone on a bus until SIGINT/SIGTERM or --frames; prints its counters",
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
};

// CLI11 would only say "A subcommand is required" for a misspelt one.
void refuse_unknown_subcommand(int argc, char** argv) {
  const std::string first = argc >= 2 ? argv[1] : "";
  if (first.empty() || first[0] == '-') return;
  std::vector<std::string> names;
  for (const Subcommand& subcommand : kSubcommands) {
    if (first == subcommand.name) return;
    names.emplace_back(subcommand.name);
  }
  throw UsageError("unknown subcommand '" + first + "' (expected " +
                   join_choices(names, ", ", " or ") + "; see stickslip --help)");
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
  app.footer(
      "Exit status: 0 success, 1 bad input data or failed file operation, 2 command-line error.");
  std::vector<std::unique_ptr<Command>> commands;
  std::vector<CLI::App*> apps;
  for (const Subcommand& subcommand : kSubcommands) {
    commands.push_back(subcommand.make());
    apps.push_back(app.add_subcommand(subcommand.name, subcommand.description));
    commands.back()->add_options(*apps.back());
  }
  refuse_unknown_subcommand(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) {  // --help
      out << app.help();
      return kExitOk;
    }
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitUsage;
  }
  for (std::size_t i = 0; i < commands.size(); ++i)
    if (apps[i]->parsed()) return commands[i]->run(*apps[i], out, err);
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

bool given(const CLI::App& command, const char* option) {
  const CLI::Option* found = command.get_option_no_throw(option);
  return found != nullptr && found->count() > 0;
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
