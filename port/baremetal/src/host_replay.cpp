// The node's replay on the host: the same node.cpp, the same lib/ node and core, compiled for the
// host, fed the same stickslip-input.bin (frames of a candump log, replay.hpp), writes the same
// output frames and step records as the target under QEMU (board_qemu.cpp) —
// tools/qemu-compare.sh compares the files byte for byte.
//   stickslip_node_replay_<scalar> INPUT.bin FRAMES.bin RECORDS.bin
#include <cstdio>
#include <cstdlib>

#include "board.hpp"
#include "node.hpp"
#include "replay.hpp"

extern "C" void CAN0_IRQHandler();

namespace {

std::FILE* input = nullptr;
std::FILE* outputs[2] = {nullptr, nullptr};

struct ReadInput {
  std::size_t operator()(std::uint8_t* buffer, std::size_t capacity) const {
    return std::fread(buffer, 1, capacity, input);
  }
};
struct WriteOutput {
  void operator()(int file, const std::uint8_t* bytes, std::size_t count) const {
    if (std::fwrite(bytes, 1, count, outputs[file]) != count) {
      std::fprintf(stderr, "stickslip_node_replay: write failed\n");
      std::exit(1);
    }
  }
};
Replay<ReadInput, WriteOutput> replay{ReadInput{}, WriteOutput{}};

stickslip::can::Frame pending;
bool has_pending = false;
bool stepped = false;  // the node stepped the seat for the frame being delivered

}  // namespace

extern "C" void board_start() {}
extern "C" bool board_can_read(stickslip::can::Frame* frame) {
  if (!has_pending) return false;
  read_mailbox(*frame, pending);
  has_pending = false;
  return true;
}
extern "C" void board_can_send(const stickslip::can::Frame* frame) {
  replay.sent(*frame);
}
extern "C" void board_node_sampled() {
  stepped = true;
}
extern "C" void board_idle() {}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s INPUT.bin FRAMES.bin RECORDS.bin\n", argv[0]);
    return 2;
  }
  input = std::fopen(argv[1], "rb");
  outputs[0] = std::fopen(argv[2], "wb");
  outputs[1] = std::fopen(argv[3], "wb");
  if (input == nullptr || outputs[0] == nullptr || outputs[1] == nullptr) {
    std::fprintf(stderr, "stickslip_node_replay: cannot open %s, %s or %s\n", argv[1], argv[2],
                 argv[3]);
    return 1;
  }
  if (const int status = stickslip_node_start(); status != 0) {
    std::fprintf(stderr, "stickslip_node_replay: configure failed (status %d)\n", status);
    return 1;
  }
  while (replay.next_frame(&pending)) {
    has_pending = true;
    stepped = false;
    CAN0_IRQHandler();
    if (stepped) replay.sampled();
    replay.flush_if_half_full();
  }
  replay.flush();
  return std::fclose(outputs[0]) == 0 && std::fclose(outputs[1]) == 0 ? 0 : 1;
}
