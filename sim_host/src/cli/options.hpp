// The options of one subcommand as the command files declare and read them: a thin layer over
// CLI11's App and Option whose members are defined in options.cpp. Only options.cpp and cli.cpp
// include CLI11: its header defines its validators, formatter and config parser in every
// translation unit that includes it, about 6 s of compile time each (15 s under the
// sanitizers), whether or not the unit uses them. Private to the host library.
#pragma once

#include <cstddef>
#include <deque>
#include <string>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace stickslip::host {

// Checks of a number at parse time (the message names the option and the value).
enum class OptionCheck {
  positive,      // a finite number > 0
  non_negative,  // a finite number >= 0
  at_least_one,  // a whole number >= 1
};

// One declared option; the setters return the option, so that declarations chain as in CLI11.
class Option {
 public:
  explicit Option(CLI::Option* option) : option_(option) {}

  Option* required();
  // --help shows the variable's value at declaration as the default.
  Option* capture_default_str();
  Option* default_str(const std::string& text);
  Option* group(const std::string& heading);
  // A list option: one argument split at `separator`.
  Option* delimiter(char separator);
  Option* check(OptionCheck check);

  // How many times the user gave it (0: the default stands).
  std::size_t count() const;
  std::string name() const;
  // The value as the user typed it.
  std::string text() const;

 private:
  CLI::Option* option_;
};

class Options {
 public:
  explicit Options(CLI::App& app) : app_(&app) {}

  // `value` receives the parsed option and must outlive the parse. Declared for the value types
  // the commands use (options.cpp); another type is a link error.
  template <typename T>
  Option* add_option(const std::string& name, T& value, const std::string& description);
  Option* add_flag(const std::string& name, bool& value, const std::string& description);
  // An option declared before (std::logic_error if there is none: a defect of the command).
  Option* get_option(const std::string& name);

  CLI::App& app() const { return *app_; }

 private:
  CLI::App* app_;
  std::deque<Option> options_;  // stable addresses for the pointers handed out
};

// Whether the user gave the option on this subcommand (not merely its default); false for an
// undeclared name.
bool given(const Options& command, const char* option);

}  // namespace stickslip::host
