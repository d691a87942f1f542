// The recording options of every command that reads a recording (simulate, replay, play, record,
// sweep, advise, psd, fit): --signal, --dbc, --channel, --time, --rate, --unit, --gaps and the
// model's step --dt, declared once as an option group. Private to the host library.
#pragma once

#include "options.hpp"

#include <iosfwd>
#include <string>

#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

class RecordingOptionGroup {
 public:
  // `with_dt`: declare --dt (the model's step) too; commands with their own --dt pass false and
  // set RecordingOptions::dt_s themselves. `with_rate` false: the command's --rate means
  // something else (replay's pace), so text inputs need a time column there.
  void add_to(Options& command, bool with_dt = true, bool with_rate = true);
  // The parsed options (--gaps checked: UsageError naming the value; --rate and --dt are
  // checked as they are parsed).
  RecordingOptions resolve() const;

 private:
  RecordingOptions options_;
  std::string gaps_ = "refuse";
};

// The report's line on `err` when anything was done to the samples.
void print_recording_report(std::ostream& err, const std::string& path,
                            const RecordingReport& report);

}  // namespace stickslip::host
