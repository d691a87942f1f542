// The node's replay on the host: the same node.cpp and the same core, compiled for the host, fed
// the same stickslip-input.bin, writes the same records as the target under QEMU (board_qemu.cpp)
// — tools/qemu-compare.sh compares the two files byte for byte.
//   stickslip_node_replay_<scalar> INPUT.bin OUTPUT.bin
#include <cstdio>
#include <cstdlib>

#include "board.hpp"
#include "node.hpp"
#include "replay.hpp"

extern "C" void CAN0_IRQHandler();

namespace {

std::FILE* input = nullptr;
std::FILE* output = nullptr;

struct ReadInput {
  std::size_t operator()(std::uint8_t* buffer, std::size_t capacity) const {
    return std::fread(buffer, 1, capacity, input);
  }
};
struct WriteOutput {
  void operator()(const std::uint8_t* bytes, std::size_t count) const {
    if (std::fwrite(bytes, 1, count, output) != count) {
      std::fprintf(stderr, "stickslip_node_replay: write failed\n");
      std::exit(1);
    }
  }
};

stickslip::can::Frame pending;
bool has_pending = false;

}  // namespace

extern "C" void board_start() {}
extern "C" bool board_can_read(stickslip::can::Frame* frame) {
  if (!has_pending) return false;
  *frame = pending;
  has_pending = false;
  return true;
}
extern "C" void board_can_send(const stickslip::can::Frame* /*frame*/) {}
extern "C" void board_idle() {}

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s INPUT.bin OUTPUT.bin\n", argv[0]);
    return 2;
  }
  input = std::fopen(argv[1], "rb");
  output = std::fopen(argv[2], "wb");
  if (input == nullptr || output == nullptr) {
    std::fprintf(stderr, "stickslip_node_replay: cannot open %s or %s\n", argv[1], argv[2]);
    return 1;
  }
  if (const int status = stickslip_node_start(); status != 0) {
    std::fprintf(stderr, "stickslip_node_replay: configure failed (status %d)\n", status);
    return 1;
  }
  Replay<ReadInput, WriteOutput> replay{ReadInput{}, WriteOutput{}};
  while (replay.next_frame(&pending)) {
    has_pending = true;
    CAN0_IRQHandler();
    replay.record();
  }
  replay.flush();
  return std::fclose(output) == 0 ? 0 : 1;
}
