// The trace CSV that simulate, replay and ecu write: one row per sample, the columns of
// kTraceCsvHeader, every number "%.17g" (so a float run reads back exactly as double). One
// writer for all of them, so that replay's file can be compared with simulate's byte for byte.
#pragma once

#include "stickslip/host/io/output_file.hpp"

namespace stickslip::host {

inline constexpr const char* kTraceCsvHeader = "t,a_u,x_r,v_r,a_x,f_f,stuck";

// One sample of the trace, in SI units.
struct TraceRow {
  double t_s = 0.0;
  double a_u_m_per_s2 = 0.0;
  double x_r_m = 0.0;
  double v_r_m_per_s = 0.0;
  double a_x_m_per_s2 = 0.0;
  double friction_n = 0.0;
  bool stuck = false;
};

// Writes the header on construction, then one line per row(); flush() hands the rows to the file
// (the caller commits it).
class TraceCsvWriter {
 public:
  // `header` false: more rows of a trace whose header is written (the parts of a split run).
  explicit TraceCsvWriter(CsvWriter& writer, bool header = true) : writer_(writer) {
    if (!header) return;
    writer_.text(kTraceCsvHeader);
    writer_.text("\n");
  }

  void row(const TraceRow& r) {
    writer_.number(r.t_s);
    writer_.separator();
    writer_.number(r.a_u_m_per_s2);
    writer_.separator();
    writer_.number(r.x_r_m);
    writer_.separator();
    writer_.number(r.v_r_m_per_s);
    writer_.separator();
    writer_.number(r.a_x_m_per_s2);
    writer_.separator();
    writer_.number(r.friction_n);
    writer_.separator();
    writer_.flag(r.stuck);
    writer_.end_row();
  }

  void flush() { writer_.flush(); }

 private:
  CsvWriter& writer_;
};

}  // namespace stickslip::host
