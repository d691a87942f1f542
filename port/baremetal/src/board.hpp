// What the firmware needs from a board: its CAN driver and an idle wait. board_none.cpp gives
// weak no-op defaults (the ELF links without a board); a board support file overrides them.
#pragma once

#include "stickslip/can/frame.hpp"

extern "C" {
// Clocks, the CAN controller and its receive interrupt (CAN0_IRQHandler, IRQ 0).
void board_start();
// Pops one received frame into *frame: true if there was one.
bool board_can_read(stickslip::can::Frame* frame);
// Queues one frame for transmission (drops it if the mailbox is full).
void board_can_send(const stickslip::can::Frame* frame);
// Called after the node has stepped the seat for one sample and sent its frames (a board that
// records the run reads stickslip_node_record() here; none needs to).
void board_node_sampled();
// Waits for the next interrupt.
void board_idle();
}
