// `stickslip demo`: the tour of the toolkit in one command (generate, simulate three ways,
// replay over a bus, compare bit for bit), printed for a reader.
#pragma once

#include <iosfwd>
#include <string>

namespace stickslip::host {

struct DemoRequest {
  double duration_s = 120.0;
  double dt_s = 1e-3;
  double friction_n = 45.0;                // F_fk = F_fs
  std::string out_dir = "stickslip-demo";  // in the working directory, for the reader to open
  std::string bus;                         // replay bus; empty: port::default_bus_name()
  bool no_clobber = false;                 // refuse to replace a file an earlier demo wrote
};

// Lorry recording (rms 0.35 m/s^2, seed 1) -> signum and stick-slip on the reference system ->
// a table and one sentence on which model the scene needs; then the recording replayed as CAN
// frames over the bus to the ECU node (stick-slip), with its fault counters and the check that
// simulate on the quantised samples gives the same output bit for bit; printed to `out`.
void run_demo(const DemoRequest& request, std::ostream& out);

}  // namespace stickslip::host
