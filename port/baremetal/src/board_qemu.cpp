// QEMU's mps2 boards (mps2-an385: Cortex-M3, runs the Cortex-M0+ build; mps2-an386: Cortex-M4F)
// with semihosting: the "CAN controller" delivers the frames of stickslip-input.bin one frame per
// interrupt, the frames the node sends go to stickslip-frames.bin and its step records to
// stickslip-records.bin (replay.hpp), and the figures of the run to the console. Under `-icount
// shift=0` one instruction advances the virtual clock by 1 ns, so SysTick (processor clock, 25 MHz
// on mps2) counts one tick per 40 instructions: the total over the run gives the instructions per
// frame.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "node.hpp"
#include "replay.hpp"
#include "semihosting.hpp"

extern "C" void CAN0_IRQHandler();
extern "C" std::uint32_t __bss_end, __stack_top;  // linker script

namespace {

using semihosting::exit_with;
using semihosting::kSysRead;
using semihosting::kSysWrite;
using semihosting::open_file;
using semihosting::print;
using semihosting::print_number;

int input_file = -1, output_files[2] = {-1, -1};

struct ReadInput {
  std::size_t operator()(std::uint8_t* buffer, std::size_t capacity) const {
    const std::uintptr_t block[3] = {static_cast<std::uintptr_t>(input_file),
                                     reinterpret_cast<std::uintptr_t>(buffer), capacity};
    return capacity -
           static_cast<std::size_t>(semihosting::call(kSysRead, block));  // returns bytes NOT read
  }
};
struct WriteOutput {
  void operator()(int file, const std::uint8_t* bytes, std::size_t count) const {
    const std::uintptr_t block[3] = {static_cast<std::uintptr_t>(output_files[file]),
                                     reinterpret_cast<std::uintptr_t>(bytes), count};
    if (semihosting::call(kSysWrite, block) != 0) {
      print("board_qemu: cannot write stickslip-frames.bin / stickslip-records.bin\n");
      exit_with(false);
    }
  }
};
Replay<ReadInput, WriteOutput> replay{ReadInput{}, WriteOutput{}};

stickslip::can::Frame pending;
bool has_pending = false;
bool stepped = false;  // the node stepped the seat for the frame being delivered

// SysTick, free running from the processor clock.
volatile std::uint32_t* const kSysTick = reinterpret_cast<volatile std::uint32_t*>(0xE000E010u);
constexpr std::uint32_t kTicksMask = 0xFFFFFFu;
constexpr std::uint64_t kInstructionsPerTick = 40;  // 25 MHz processor clock, 1 ns per instruction

std::uint64_t frames = 0, ticks = 0, worst_ticks = 0;
std::uint64_t worst_frame = 0;  // its index from 0: the frame to trace (-d exec) when it is slow
// Frames by instructions, in buckets of 100 (the last one: 100 * (kBuckets - 1) and more), for
// the percentiles.
constexpr int kBuckets = 2001;
std::uint32_t histogram[kBuckets] = {};
std::uintptr_t callback_stack_base = 0;  // an address in board_idle's frame, above the callback's
constexpr std::uint32_t kStackPaint = 0x5AC3A55Au;

}  // namespace

extern "C" void board_start() {
  // Paint the free stack (below this frame) to measure its high-water mark at the end.
  std::uint32_t here = 0;
  for (std::uint32_t* word = &__bss_end; word + 16 < &here; ++word) *word = kStackPaint;
  input_file = open_file("stickslip-input.bin", 1);         // "rb"
  output_files[0] = open_file("stickslip-frames.bin", 5);   // "wb"
  output_files[1] = open_file("stickslip-records.bin", 5);  // "wb"
  if (input_file < 0 || output_files[0] < 0 || output_files[1] < 0) {
    print(
        "board_qemu: cannot open stickslip-input.bin / stickslip-frames.bin / "
        "stickslip-records.bin\n");
    exit_with(false);
  }
  kSysTick[1] = kTicksMask;  // reload
  kSysTick[2] = 0;           // current
  kSysTick[0] = 5;           // enable, processor clock, no interrupt
}

extern "C" bool board_can_read(stickslip::can::Frame* frame) {
  if (!has_pending) return false;
  read_mailbox(*frame, pending);
  has_pending = false;
  return true;
}

// The mailbox: the frame's record appended to a buffer (in the interrupt, as a driver's copy
// into the transmit mailbox would be).
extern "C" void board_can_send(const stickslip::can::Frame* frame) {
  replay.sent(*frame);
}
extern "C" void board_node_sampled() {
  stepped = true;
}

#ifdef STICKSLIP_PROFILE_FRAME
// Called just before and just after the interrupt of frame STICKSLIP_PROFILE_FRAME (a profiling
// build only): tools/qemu-frame-profile.sh breaks here to log that one frame's instructions.
extern "C" __attribute__((noinline)) void board_profile_mark() {
  asm volatile("" ::: "memory");
}
#endif

extern "C" void board_idle() {
  if (replay.next_frame(&pending)) {
    has_pending = true;
    stepped = false;
    volatile std::uint32_t marker = 0;
    callback_stack_base = reinterpret_cast<std::uintptr_t>(&marker);
    const std::uint32_t before = kSysTick[2];
#ifdef STICKSLIP_PROFILE_FRAME
    if (frames == STICKSLIP_PROFILE_FRAME) board_profile_mark();
#endif
    CAN0_IRQHandler();  // the receive interrupt, as the controller would raise it
    const std::uint32_t after = kSysTick[2];
#ifdef STICKSLIP_PROFILE_FRAME
    if (frames == STICKSLIP_PROFILE_FRAME) board_profile_mark();
#endif
    const std::uint32_t elapsed = (before - after) & kTicksMask;  // counts down
    ticks += elapsed;
    if (elapsed > worst_ticks) {
      worst_ticks = elapsed;
      worst_frame = frames;
    }
    const std::uint64_t bucket = elapsed * kInstructionsPerTick / 100u;
    ++histogram[bucket < kBuckets ? bucket : kBuckets - 1];
    ++frames;
    if (stepped) replay.sampled();
    replay.flush_if_half_full();
    return;
  }
  replay.flush();
  const std::uint32_t* lowest = &__bss_end;
  while (lowest < &__stack_top && *lowest == kStackPaint) ++lowest;
  print("frames ");
  print_number(frames);
  print("\ninstructions_per_frame_mean ");
  print_number(frames != 0 ? ticks * kInstructionsPerTick / frames : 0);
  // Upper edges of the buckets holding the 50th, 99th and 99.9th percentile.
  const std::uint64_t ranks[3] = {frames / 2, frames - frames / 100, frames - frames / 1000};
  const char* const names[3] = {"\ninstructions_per_frame_p50 ", "\ninstructions_per_frame_p99 ",
                                "\ninstructions_per_frame_p999 "};
  for (int i = 0; i < 3; ++i) {
    std::uint64_t below = 0;
    int bucket = 0;
    while (bucket < kBuckets - 1 && below + histogram[bucket] < ranks[i])
      below += histogram[bucket++];
    print(names[i]);
    print_number(100u * static_cast<std::uint64_t>(bucket + 1));
  }
  print("\ninstructions_per_frame_max ");
  print_number(worst_ticks * kInstructionsPerTick);
  print("\nworst_frame_index ");
  print_number(worst_frame);
  // The deepest stack below board_idle's frame: the receive interrupt, the step and what they
  // call (board_idle's own locals above the marker excluded).
  print("\ncallback_stack_bytes ");
  print_number(
      static_cast<std::uint64_t>(callback_stack_base - reinterpret_cast<std::uintptr_t>(lowest)));
  print("\n");
  exit_with(true);
}
