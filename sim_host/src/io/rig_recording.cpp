#include "stickslip/host/io/rig_recording.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <string>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/delimited_text.hpp"

namespace stickslip::host {
namespace {

constexpr std::size_t kMinimumSamples = 16;
constexpr double kStandardGravity_m_per_s2 = 9.80665;

const TextChannel* find_channel(const DelimitedTable& table, const char* name) {
  for (const TextChannel& channel : table.channels)
    if (channel.name == name) return &channel;
  return nullptr;
}

std::string column_list(const DelimitedTable& table) {
  std::string names;
  for (const TextChannel& channel : table.channels)
    names += (names.empty() ? "" : ", ") + channel.name;
  return names;
}

bool is_acceleration_si(const std::string& unit) {
  return unit.empty() || unit == "m/s^2" || unit == "m/s\xc2\xb2" || unit == "m/s2" ||
         unit == "m s^-2" || unit == "m*s^-2";
}

bool is_gravity_unit(const std::string& unit) {
  return unit == "g" || unit == "G" || unit == "g0" || unit == "gn";
}

void check_acceleration_unit(const std::string& path, const TextChannel& channel) {
  if (is_acceleration_si(channel.unit)) return;
  if (is_gravity_unit(channel.unit)) {
    throw HostError(fmt::format(
        "{}: column '{}' is in {} but the fit needs m/s^2; multiply it by {} and name the unit "
        "m/s^2",
        path, channel.name, channel.unit, kStandardGravity_m_per_s2));
  }
  throw HostError(fmt::format("{}: column '{}' is in '{}' but the fit needs m/s^2", path,
                              channel.name, channel.unit));
}

const TextChannel& required(const DelimitedTable& table, const char* name, const char* what) {
  const TextChannel* channel = find_channel(table, name);
  if (channel == nullptr) {
    throw HostError(fmt::format("{}: no column '{}' ({}); the columns are: {}", table.path, name,
                                what, column_list(table)));
  }
  return *channel;
}

void check_time_base(RigRecording& rig) {
  const std::size_t n = rig.t_s.size();
  if (n < kMinimumSamples) {
    throw HostError(
        fmt::format("{}: {} samples; the fit needs at least {}", rig.path, n, kMinimumSamples));
  }
  rig.dt_s = (rig.t_s.back() - rig.t_s.front()) / static_cast<double>(n - 1);
  const double first = rig.t_s[1] - rig.t_s[0];
  if (!(first > 0.0))
    throw HostError(fmt::format("{}: t must increase (row 2: t = {} after {})", rig.path,
                                rig.t_s[1], rig.t_s[0]));
  for (std::size_t i = 1; i < n; ++i) {
    const double step = rig.t_s[i] - rig.t_s[i - 1];
    if (std::fabs(step - first) > kUniformStepTolerance * first) {
      throw HostError(
          fmt::format("{}: t is not uniform: data row {} steps {} s after a first step of {} s",
                      rig.path, i + 1, step, first));
    }
  }
}

}  // namespace

RigRecording read_rig_recording(const std::string& path) {
  const DelimitedTable table = read_delimited_text(path);
  const TextChannel& t = required(table, "t", "the time, s");
  const TextChannel& a_u = required(table, "a_u", "the cab-floor acceleration, m/s^2");
  const TextChannel& a_x =
      required(table, "a_x", "the seat acceleration, m/s^2, which the fit compares the model with");
  if (!t.unit.empty() && t.unit != "s")
    throw HostError(fmt::format("{}: column 't' is in '{}' but the fit needs s", path, t.unit));
  check_acceleration_unit(path, a_u);
  check_acceleration_unit(path, a_x);
  RigRecording rig;
  rig.path = path;
  rig.t_s = t.values;
  rig.a_u_m_per_s2 = a_u.values;
  rig.a_x_m_per_s2 = a_x.values;
  if (const TextChannel* x_r = find_channel(table, "x_r")) {
    if (!x_r->unit.empty() && x_r->unit != "m") {
      throw HostError(
          fmt::format("{}: column 'x_r' is in '{}' but the fit needs m", path, x_r->unit));
    }
    rig.x_r_m = x_r->values;
  }
  check_time_base(rig);
  return rig;
}

}  // namespace stickslip::host
