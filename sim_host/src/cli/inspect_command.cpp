// stickslip inspect: what a recording holds and the simulate line that reads it (inspect.hpp).
#include <ostream>

#include "command.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/run/inspect.hpp"

namespace stickslip::host {
namespace {

class InspectCommand : public Command {
 public:
  void add_options(Options& inspect) override {
    inspect.add_option("file", path_, "recording: text, .mat, or a CAN log")->required();
    inspect.add_option("--dbc", options_.dbc, "DBC file: decode a CAN log's signals");
    inspect.add_option("--signal", options_.signal,
                       "the signal to suggest (default: the first "
                       "with an acceleration unit)");
    inspect.add_option("--channel", options_.channel,
                       "CAN log: describe the frames of this bus only (the log's channels are "
                       "listed without it)");
    inspect.add_option("--time", options_.time, "text: the time column");
    inspect.add_option("--rate", options_.rate_hz, "text without a time column: sample rate, Hz");
  }

  int run(Options&, std::ostream& out, std::ostream&) override {
    out << inspect_recording(path_, options_);
    return kExitOk;
  }

 private:
  std::string path_;
  RecordingOptions options_;
};

}  // namespace

std::unique_ptr<Command> make_inspect_command() {
  return std::make_unique<InspectCommand>();
}

}  // namespace stickslip::host
