#include "options.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <stdexcept>
#include <vector>

namespace stickslip::host {
namespace {

CLI::Validator at_least_one() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        std::size_t end = 0;
        long long number = 0;
        try {
          number = std::stoll(value, &end);
        } catch (const std::exception&) {
          end = 0;
        }
        if (end == value.size() && end > 0 && number >= 1) return "";
        return "must be a whole number >= 1, got '" + value + "'";
      },
      "N >= 1");
}

// CLI11's PositiveNumber and NonNegativeNumber state their upper bound, the largest double, in
// 309 digits; this states the rule. Infinity and NaN are refused: no option means them.
CLI::Validator finite_number(bool zero_allowed) {
  return CLI::Validator(
      [zero_allowed](std::string& value) -> std::string {
        std::size_t end = 0;
        double number = std::numeric_limits<double>::quiet_NaN();
        try {
          number = std::stod(value, &end);
        } catch (const std::exception&) {
          end = 0;
        }
        // isfinite first: an ordered comparison with NaN raises FE_INVALID.
        const bool in_range =
            std::isfinite(number) && (number > 0.0 || (zero_allowed && number == 0.0));
        if (end == value.size() && end > 0 && in_range) return "";
        return std::string("must be a finite number ") + (zero_allowed ? ">= 0" : "> 0") +
               ", got " + value;
      },
      zero_allowed ? "NONNEGATIVE" : "POSITIVE");
}

}  // namespace

Option* Option::required() {
  option_->required();
  return this;
}

Option* Option::capture_default_str() {
  option_->capture_default_str();
  return this;
}

Option* Option::default_str(const std::string& text) {
  option_->default_str(text);
  return this;
}

Option* Option::group(const std::string& heading) {
  option_->group(heading);
  return this;
}

Option* Option::delimiter(char separator) {
  option_->delimiter(separator);
  return this;
}

Option* Option::check(OptionCheck check) {
  switch (check) {
    case OptionCheck::positive:
      option_->check(finite_number(false));
      break;
    case OptionCheck::non_negative:
      option_->check(finite_number(true));
      break;
    case OptionCheck::at_least_one:
      option_->check(at_least_one());
      break;
  }
  return this;
}

std::size_t Option::count() const {
  return option_->count();
}

std::string Option::name() const {
  return option_->get_name();
}

std::string Option::text() const {
  return option_->as<std::string>();
}

template <typename T>
Option* Options::add_option(const std::string& name, T& value, const std::string& description) {
  return &options_.emplace_back(app_->add_option(name, value, description));
}

template Option* Options::add_option(const std::string&, double&, const std::string&);
template Option* Options::add_option(const std::string&, int&, const std::string&);
template Option* Options::add_option(const std::string&, std::uint16_t&, const std::string&);
template Option* Options::add_option(const std::string&, unsigned&, const std::string&);
template Option* Options::add_option(const std::string&, std::uint64_t&, const std::string&);
template Option* Options::add_option(const std::string&, std::string&, const std::string&);
template Option* Options::add_option(const std::string&, std::vector<double>&, const std::string&);
template Option* Options::add_option(const std::string&, std::vector<std::string>&,
                                     const std::string&);

Option* Options::add_flag(const std::string& name, bool& value, const std::string& description) {
  return &options_.emplace_back(app_->add_flag(name, value, description));
}

Option* Options::get_option(const std::string& name) {
  CLI::Option* option = app_->get_option_no_throw(name);
  if (option == nullptr) throw std::logic_error(app_->get_name() + " declares no option " + name);
  return &options_.emplace_back(option);
}

bool given(const Options& command, const char* option) {
  const CLI::Option* found = command.app().get_option_no_throw(option);
  return found != nullptr && found->count() > 0;
}

}  // namespace stickslip::host
