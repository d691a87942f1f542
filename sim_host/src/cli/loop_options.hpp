// The controller's options, shared by closed-loop (in process) and controller (over a bus), so
// that the same flags configure the same ControlUnit. Private to the host library.
#pragma once

#include "options.hpp"

#include <string>

#include "stickslip/host/run/closed_loop.hpp"

namespace stickslip::host {

// --a-x-noise and --x-r-noise: the plant's sensor noise (closed-loop and plant).
void add_sensor_noise_options(Options& command, ClosedLoopSetup& setup);

class LoopControllerOptions {
 public:
  void add_to(Options& command, ClosedLoopSetup& setup);
  // Parses --controller and --observer into `setup`; friction-compensation alone feeds 0.8
  // forward unless --friction-compensation is given. Throws UsageError.
  void resolve(const Options& command, ClosedLoopSetup& setup) const;

 private:
  std::string controller_ = "passive";
  std::string observer_ = "estimator";
};

}  // namespace stickslip::host
