#include "stickslip/host/run/fit_report.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "fit_start.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/gnuplot_png.hpp"

namespace stickslip::host {
namespace {

std::string estimate_line(const FitResult& result, FitParameter parameter) {
  const auto k = static_cast<std::size_t>(parameter);
  const char* name = fit_parameter_name(parameter);
  if (!std::isfinite(result.ci95[k]))
    return fmt::format("  {:<18} not identifiable on this recording\n", name);
  return fmt::format("  {:<18} {:.6g} +- {:.3g} {} (95 %, +-{:.2g} %)\n", name, result.value[k],
                     result.ci95[k], fit_parameter_unit(parameter),
                     100.0 * result.ci95[k] / std::fabs(result.value[k]));
}

std::string correlation_lines(const FitResult& result) {
  std::string text = fmt::format("correlation of the estimates (condition number {:.3g}):\n",
                                 result.condition_number);
  text += fmt::format("  {:<18}", "");
  for (FitParameter parameter : result.order)
    text += fmt::format(" {:>9.9}", fit_parameter_name(parameter));
  text += "\n";
  for (std::size_t i = 0; i < result.order.size(); ++i) {
    text += fmt::format("  {:<18}", fit_parameter_name(result.order[i]));
    for (std::size_t j = 0; j < result.order.size(); ++j) {
      const double rho = result.correlation[i][j];
      text += std::isfinite(rho) ? fmt::format(" {:>+9.3f}", rho) : fmt::format(" {:>9}", "-");
    }
    text += "\n";
  }
  return text;
}

}  // namespace

std::string fit_report_text(const FitResult& result) {
  std::string text =
      fmt::format("fit: {} model, converged after {} iterations in {:.2f} s\n",
                  model_name(result.params.model), result.iterations, result.seconds);
  text += "estimates (95 % intervals from the Gauss-Newton covariance, residual variance):\n";
  for (FitParameter parameter : result.order) text += estimate_line(result, parameter);
  if (!result.fitted[static_cast<std::size_t>(FitParameter::mass)])
    text += fmt::format("  {:<18} {:.6g} kg (given)\n", "mass", result.params.mass_kg);
  text += fmt::format("rms residual a_x: {:.4g} m/s^2 (white noise in a_x estimated at {:.3g})\n",
                      result.rms_residual_m_per_s2, result.noise_m_per_s2);
  if (result.rms_travel_residual_m > 0.0)
    text += fmt::format("rms residual x_r: {:.4g} m\n", result.rms_travel_residual_m);
  for (const FitSegment& part : result.segments) {
    text += fmt::format("part from t = {} s: {} samples, rms residual a_x {:.4g} m/s^2\n",
                        part.t_start_s, part.samples, part.rms_residual_m_per_s2);
  }
  text += fmt::format("T_ax: measured {:.4f}, model {:.4f}\n", result.transmissibility_measured,
                      result.transmissibility_model);
  text += fmt::format(
      "p (share of time stuck): measured {:.4f} (seen from a phase's sample {} on), model {:.4f}\n",
      result.stick_probability_measured, kStuckFilterSamples, result.stick_probability_model);
  text += correlation_lines(result);
  for (const std::string& warning : result.warnings) text += "warning: " + warning + "\n";
  return text;
}

std::string fit_json(const FitResult& result) {
  nlohmann::ordered_json json;
  for (FitParameter parameter : result.order) {
    const auto k = static_cast<std::size_t>(parameter);
    const std::string name = fit_parameter_name(parameter);
    json[name] = result.value[k];
    if (std::isfinite(result.ci95[k])) {
      json[name + "_ci95"] = result.ci95[k];
    } else {
      json[name] = nullptr;  // not identifiable: no estimate to print
      json[name + "_ci95"] = nullptr;
    }
  }
  json["rms_residual"] = result.rms_residual_m_per_s2;
  json["T_ax_measured"] = result.transmissibility_measured;
  json["T_ax_model"] = result.transmissibility_model;
  json["p_measured"] = result.stick_probability_measured;
  json["p_model"] = result.stick_probability_model;
  json["condition_number"] = std::isfinite(result.condition_number)
                                 ? nlohmann::ordered_json(result.condition_number)
                                 : nlohmann::ordered_json(nullptr);
  json["iterations"] = result.iterations;
  json["seconds"] = result.seconds;
  json["converged"] = result.converged;
  if (!result.segments.empty()) {  // --gaps split: each part, simulated alone
    auto& parts = json["segments"] = nlohmann::ordered_json::array();
    for (const FitSegment& segment : result.segments) {
      nlohmann::ordered_json part;
      part["t_start_s"] = segment.t_start_s;
      part["samples"] = segment.samples;
      part["rms_residual"] = segment.rms_residual_m_per_s2;
      parts.push_back(part);
    }
  }
  return json.dump();
}

void write_residual_plot(const RigRecording& rig, const FitResult& result,
                         const std::string& png_path) {
  const std::string stem = fmt::format("{}.{}.tmp", png_path, static_cast<long>(getpid()));
  const std::string data_path = stem + ".dat", image_path = stem + ".png";
  {
    AtomicOutputFile data(data_path);
    std::string rows;
    for (std::size_t n = 0; n < result.residual_m_per_s2.size(); ++n)
      rows += fmt::format("{} {}\n", rig.t_s[n], result.residual_m_per_s2[n]);
    data.write(rows);
    data.commit();
  }
  const std::string script = fmt::format(
      "set terminal png size 1200,500; set output '{}'; set xlabel 't (s)'; "
      "set ylabel 'a_x measured - model (m/s^2)'; set grid; "
      "set title 'stickslip fit: {} model, rms residual {:.3g} m/s^2'; "
      "plot '{}' using 1:2 with lines lw 1 notitle",
      image_path, model_name(result.params.model), result.rms_residual_m_per_s2, data_path);
  draw_png(script, data_path, image_path, png_path, "the residual plot");
}

}  // namespace stickslip::host
