// The subcommands of the sweep issue (sweep, merge, psd, harmonic-balance, advise), registered
// on the command line by cli.cpp through these two calls so that cli.cpp stays a short list.
// Private to the host library: it exposes CLI11.
#pragma once

#include <CLI/CLI.hpp>

#include <iosfwd>
#include <memory>
#include <string>

namespace stickslip::host {

struct ExtraCommandOptions;  // the options' storage, alive while the App parses

struct ExtraCommands {
  ExtraCommands();
  ~ExtraCommands();
  ExtraCommands(const ExtraCommands&) = delete;
  ExtraCommands& operator=(const ExtraCommands&) = delete;

  void add_to(CLI::App& app);
  static bool is_name(const std::string& subcommand);
  static const char* names();  // "sweep, merge, psd, harmonic-balance or advise"
  // Runs the parsed subcommand if it is one of these; returns false otherwise.
  bool run(CLI::App& app, std::ostream& out, std::ostream& err, int& status);

 private:
  std::unique_ptr<ExtraCommandOptions> options_;
};

}  // namespace stickslip::host
