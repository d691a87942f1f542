// The CAN codec and receive checker are header code; this unit compiles them the way an MCU
// build does (-fno-exceptions -fno-rtti, standard headers only) and instantiates the scalar
// templates for float and double once.
#include "stickslip/can/codec.hpp"
#include "stickslip/can/crc8.hpp"
#include "stickslip/can/receive_checker.hpp"

namespace stickslip::can {

template Quantised quantise<float>(const SignalSpec&, float) noexcept;
template Quantised quantise<double>(const SignalSpec&, double) noexcept;
template float physical<float>(const SignalSpec&, std::uint16_t) noexcept;
template double physical<double>(const SignalSpec&, std::uint16_t) noexcept;
template Frame make_input_frame<float>(float, std::uint64_t, bool*, float) noexcept;
template Frame make_input_frame<double>(double, std::uint64_t, bool*, double) noexcept;

namespace {
constexpr std::uint8_t kCheckInput[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
static_assert(crc8_sae_j1850(kCheckInput, 9) == 0x4B, "CRC-8 SAE J1850 check value");
}  // namespace

}  // namespace stickslip::can
