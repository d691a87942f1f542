// One subcommand of `stickslip`: the options it declares (stored in the object, alive while the
// App parses) and what it does once parsed. cli.cpp holds the table of them (name, description,
// factory); everything a test wants to call is in the libraries these commands call.
// Private to the host library.
#pragma once

#include "options.hpp"

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "stickslip/host/bus/bus_commands.hpp"

namespace stickslip::host {

class Command {
 public:
  virtual ~Command() = default;
  // Declares the options on the subcommand cli.cpp created under the table's name.
  virtual void add_options(Options& command) = 0;
  // Runs the parsed subcommand; returns the exit status (errors are thrown as HostError).
  virtual int run(Options& command, std::ostream& out, std::ostream& err) = 0;
};

// "a, b, c or d" (", ", " or ") for messages, "a | b | c" (" | ", " | ") for help.
std::string join_choices(const std::vector<std::string>& choices, const char* separator,
                         const char* last_separator);

// The name nearest to a mistyped one (edit distance), if near enough to be what was meant; empty
// otherwise.
std::string closest_name(const std::string& typed, const std::vector<std::string>& names);

// "; did you mean NAME?" for the closest of `names`, or "" (to end a message's "(expected ...").
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& names);

// --bus: a name one typo from "loopback" that is no interface of this machine is refused with the
// suggestion (opening it would only say "unsupported").
void check_bus_name(const char* option, const std::string& bus);

// Whether `err` is the process's stderr and that is a terminal.
bool stderr_is_terminal(const std::ostream& err);

// Progress of a command that may run for long (replay, play, ecu), called after every frame:
// `waiting` (what the command now waits for) once, at the first frame - so that an error before
// it, such as a bus that cannot be opened, stays the only line - then, when `enabled` (a
// terminal, or --progress), "WHAT: done/total frames" first after 2 s and at most once a second.
// total 0: open-ended, the count alone.
std::function<void(std::uint64_t, std::uint64_t)> make_frame_progress(std::ostream& err,
                                                                      const char* what,
                                                                      bool enabled,
                                                                      std::string waiting);

// The request's plain callback over `progress`, which must outlive the run; empty if it is.
inline BusProgress bus_progress(std::function<void(std::uint64_t, std::uint64_t)>& progress) {
  if (!progress) return {};
  BusProgress plain;
  plain.report = [](void* context, std::uint64_t done, std::uint64_t total) {
    (*static_cast<std::function<void(std::uint64_t, std::uint64_t)>*>(context))(done, total);
  };
  plain.context = &progress;
  return plain;
}

std::unique_ptr<Command> make_generate_command();
std::unique_ptr<Command> make_simulate_command();
std::unique_ptr<Command> make_demo_command();
std::unique_ptr<Command> make_replay_command();
std::unique_ptr<Command> make_ecu_command();
std::unique_ptr<Command> make_record_command();
std::unique_ptr<Command> make_play_command();
std::unique_ptr<Command> make_sweep_command();
std::unique_ptr<Command> make_merge_command();
std::unique_ptr<Command> make_psd_command();
std::unique_ptr<Command> make_harmonic_balance_command();
std::unique_ptr<Command> make_advise_command();
std::unique_ptr<Command> make_inspect_command();
std::unique_ptr<Command> make_fit_command();
std::unique_ptr<Command> make_closed_loop_command();
std::unique_ptr<Command> make_plant_command();
std::unique_ptr<Command> make_controller_command();

}  // namespace stickslip::host
