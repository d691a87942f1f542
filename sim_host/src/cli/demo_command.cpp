// stickslip demo (demo.hpp).
#include <ostream>

#include "command.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/cli/demo.hpp"

namespace stickslip::host {
namespace {

class DemoCommand : public Command {
 public:
  void add_options(Options& demo) override {
    demo.add_option("--duration", request_.duration_s, "s")->capture_default_str();
    demo.add_option("--dt", request_.dt_s, "s")->capture_default_str();
    demo.add_option("--ffk", request_.friction_n, "F_fk = F_fs, N")->capture_default_str();
    demo.add_option("--bus", request_.bus,
                    "bus for the replay (default: vcan0 where the kernel has it, else loopback)");
    demo.add_option("--out-dir", request_.out_dir,
                    "where the files a reader opens go (created if missing)")
        ->capture_default_str();
    demo.add_flag("--no-clobber", request_.no_clobber,
                  "refuse to replace the files of an earlier demo in --out-dir");
  }

  int run(Options&, std::ostream& out, std::ostream&) override {
    run_demo(request_, out);
    return kExitOk;
  }

 private:
  DemoRequest request_;
};

}  // namespace

std::unique_ptr<Command> make_demo_command() {
  return std::make_unique<DemoCommand>();
}

}  // namespace stickslip::host
