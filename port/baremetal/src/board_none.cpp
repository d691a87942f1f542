// No board attached: weak defaults that a board support file overrides.
#include "board.hpp"

extern "C" {
__attribute__((weak)) void board_start() {}
__attribute__((weak)) bool board_can_read(stickslip::can::Frame* /*frame*/) {
  return false;
}
__attribute__((weak)) void board_can_send(const stickslip::can::Frame* /*frame*/) {}
__attribute__((weak)) void board_node_sampled() {}
__attribute__((weak)) void board_idle() {
  __asm volatile("wfi");
}
}
