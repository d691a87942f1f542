#include "recording_options.hpp"

#include <ostream>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

void RecordingOptionGroup::add_to(Options& command, bool with_dt, bool with_rate) {
  // Options of the command itself (under their own heading in --help), so that every check of
  // a command's options sees them.
  const auto group = &command;
  group->add_option("--signal", options_.signal,
                    "text: column name or 1-based index (default a_u); CAN log: MESSAGE.SIGNAL "
                    "with --dbc");
  group->add_option("--dbc", options_.dbc,
                    "DBC file: read the input as a CAN log "
                    "(candump, ASC, BLF, TRC)");
  group->add_option("--channel", options_.channel,
                    "CAN log: decode the frames of this bus only (candump interface, ASC/BLF/TRC "
                    "channel number; stickslip inspect lists them)");
  group->add_option("--time", options_.time,
                    "text: the time column (default: one named t or time, or in s)");
  if (with_rate) {
    group->add_option("--rate", options_.rate_hz, "text without a time column: sample rate, Hz")
        ->group("Recording")
        ->check(OptionCheck::positive);
  }
  group->add_option("--unit", options_.unit,
                    "g | m/s^2 | mm/s^2: the signal's unit over the header's or DBC's "
                    "(g = 9.80665 m/s^2)");
  group
      ->add_option("--gaps", gaps_, "refuse | hold | split: a step over 1.5 nominal steps is a gap")
      ->capture_default_str();
  for (const char* name : {"--signal", "--dbc", "--channel", "--time", "--unit", "--gaps"})
    command.get_option(name)->group("Recording");
  if (with_dt) {
    group
        ->add_option("--dt", options_.dt_s,
                     "the model's step, s: resample the recording to it (libsoxr) when "
                     "its rate differs or its times jitter")
        ->group("Recording")
        ->check(OptionCheck::positive);
  }
}

RecordingOptions RecordingOptionGroup::resolve() const {
  RecordingOptions options = options_;
  if (!parse_gap_policy(gaps_, options.gaps))
    throw UsageError("--gaps: '" + gaps_ + "' is not refuse, hold or split");
  return options;
}

void print_recording_report(std::ostream& err, const std::string& path,
                            const RecordingReport& report) {
  const std::string line = describe_recording(path, report);
  if (!line.empty()) err << "stickslip: " << line << "\n";
}

}  // namespace stickslip::host
