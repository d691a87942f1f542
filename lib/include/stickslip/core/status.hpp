// Configuration status: what configure() returns instead of throwing.
#pragma once

#include <cstddef>
#include <cstdint>

namespace stickslip {

enum class Status : std::uint8_t {
  ok = 0,
  not_finite,            // a parameter is NaN or infinite
  out_of_range,          // a parameter is outside its physical range (e.g. mass <= 0)
  static_below_kinetic,  // F_fs < F_fk
  unstable,              // the chosen integrator is outside its stability limit for this scene
  unsupported,           // a model/integrator combination the library does not offer
};

const char* status_name(Status status) noexcept;

// A short human-readable message that names the offending parameter and the limit.
// Fixed capacity: no heap, safe to keep on an MCU.
class StatusMessage {
 public:
  static constexpr std::size_t kCapacity = 400;

  StatusMessage() noexcept { text_[0] = '\0'; }
  const char* c_str() const noexcept { return text_; }
  void clear() noexcept {
    length_ = 0;
    text_[0] = '\0';
  }
  StatusMessage& append(const char* text) noexcept;
  // Appends a number with `significant` digits in plain or scientific notation, as %g would.
  StatusMessage& append(double value, int significant = 6) noexcept;

 private:
  char text_[kCapacity];
  std::size_t length_ = 0;
};

struct ConfigResult {
  Status status = Status::ok;
  StatusMessage message;
  bool ok() const noexcept { return status == Status::ok; }
};

// A refused configuration: `status` with an empty message, which the caller fills with the
// parameter to change and the limit it broke. Every configure() refuses through this.
inline ConfigResult refusal(Status status) noexcept {
  ConfigResult result;
  result.status = status;
  return result;
}

}  // namespace stickslip
