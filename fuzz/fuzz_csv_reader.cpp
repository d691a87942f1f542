// The CSV reader on arbitrary bytes: it either returns a signal that keeps its promises (>= 2
// samples, finite values, t increasing, dt > 0 and finite) or throws HostError; nothing else
// (no crash, no sanitizer report, no other exception).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/csv_reader.hpp"

#include "fuzz_support.hpp"

namespace {

using stickslip::fuzz::check;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = stickslip::fuzz::input_as_file(data, size);
  try {
    const stickslip::host::SampledSignal signal = stickslip::host::read_signal_csv(path);
    const std::size_t n = signal.t_s.size();
    check(n >= 2 && signal.a_u_m_per_s2.size() == n);
    for (std::size_t i = 0; i < n; ++i) {
      check(std::isfinite(signal.t_s[i]) && std::isfinite(signal.a_u_m_per_s2[i]));
      if (i > 0) check(signal.t_s[i] > signal.t_s[i - 1]);
    }
    check(signal.dt_s > 0.0 && std::isfinite(signal.dt_s));
  } catch (const stickslip::host::HostError&) {
    // A refused file: the message is the product here, its content is tested in tests/host.
  }
  return 0;
}
