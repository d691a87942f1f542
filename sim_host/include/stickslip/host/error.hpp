// The host tools report a bad input or a failed operation by throwing HostError with a complete,
// one-line message ("IN.csv:17: column 'a_u': 'abc' is not a number"); run_cli() catches it,
// prefixes "stickslip: " and returns a non-zero status. The core (lib/) never throws.
#pragma once

#include <stdexcept>
#include <string>

namespace stickslip::host {

class HostError : public std::runtime_error {
 public:
  explicit HostError(const std::string& message) : std::runtime_error(message) {}
};

// A wrong command-line value (exit status 2, like a parse error) rather than bad data (status 1).
class UsageError : public HostError {
 public:
  explicit UsageError(const std::string& message) : HostError(message) {}
};

// configure() refused the parameters; what() is the core's message, which names the parameter
// (as in OscillatorParams, e.g. "mass_kg") and its limit.
class ConfigurationError : public HostError {
 public:
  explicit ConfigurationError(const std::string& core_message) : HostError(core_message) {}
};

}  // namespace stickslip::host
