// The scene (TOML) reader on arbitrary bytes: it either returns a scene or throws HostError naming
// file, line and key; nothing else. An accepted scene goes on as `simulate --scene` takes it: the
// model of exactly its effects is configured from it and, when configure() accepts, runs a few
// hundred steps of a bounded input without NaN/Inf and without the non-finite guard restarting
// the state.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "stickslip/models/scene.hpp"

#include "fuzz_support.hpp"

namespace {

using stickslip::fuzz::check;

template <typename T>
bool finite_output(const stickslip::StepOutput<T>& out) {
  return std::isfinite(out.x_r_m) && std::isfinite(out.v_r_m_per_s) &&
         std::isfinite(out.a_x_m_per_s2) && std::isfinite(out.friction_n);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = stickslip::fuzz::input_as_file(data, size);
  stickslip::host::Scene scene;
  try {
    scene = stickslip::host::read_scene_file(path);
  } catch (const stickslip::host::HostError&) {
    return 0;  // a refused file: tests/host checks the messages
  }
  const stickslip::SceneParams params = scene.core();
  stickslip::with_scene_model<double>(params, [&](auto& model) {
    if (!stickslip::configure_for_scene(model, params).ok()) return 0;
    model.reset(0.0, 0.0, 0.0);
    for (int n = 0; n < 400; ++n) {
      // A bounded 2 Hz input with a step in it, from the index (no accumulated time).
      const double a_u = 3.0 * std::sin(0.0126 * n) + (n > 200 ? 5.0 : 0.0);
      check(finite_output(model.step(a_u)));
    }
    check(model.state_resets() == 0);
    return 0;
  });
  return 0;
}
