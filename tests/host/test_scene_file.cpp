// Scene files (TOML): the effects decide the model, parameters land in OscillatorParams, and every
// contradiction or unknown name is an error that names the file, line and key.
#include <string>

#include "CppUTest/TestHarness.h"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "support/host_test_support.hpp"

using namespace stickslip;
using stickslip::host::read_scene_file;
using stickslip::host::Scene;

namespace {

std::string error_of(const std::string& toml_text) {
  test::TempDir dir;
  const std::string path = dir.file("scene.toml");
  test::write_text(path, toml_text);
  try {
    read_scene_file(path);
  } catch (const host::HostError& e) {
    const std::string message = e.what();
    // Every message starts with the file (and, from the parser, line:column).
    CHECK_TRUE(message.rfind(path + ":", 0) == 0);
    return message.substr(path.size());
  }
  return "no error";
}

Scene scene_of(const std::string& toml_text) {
  test::TempDir dir;
  const std::string path = dir.file("scene.toml");
  test::write_text(path, toml_text);
  return read_scene_file(path);
}

}  // namespace

TEST_GROUP(SceneFile){};

TEST(SceneFile, ExampleScenesInTheRepositoryLoad) {
  const std::string dir = std::string(STICKSLIP_SOURCE_DIR) + "/docs/scenes/";
  const Scene stick = read_scene_file(dir + "lorry-seat-stick-slip.toml");
  CHECK_TRUE(stick.params.model == FrictionModel::stick_slip);
  CHECK_TRUE(stick.params.integrator == Integrator::exact);
  DOUBLES_EQUAL(45.0, stick.params.static_friction_n, 0.0);
  DOUBLES_EQUAL(1e-3, stick.params.dt_s, 0.0);
  CHECK_EQUAL(0x100u, *stick.can.input_id);
  CHECK_EQUAL(0x180u, *stick.can.output_id);
  const Scene linear = read_scene_file(dir + "linear-seat.toml");
  CHECK_TRUE(linear.params.model == FrictionModel::linear);
  DOUBLES_EQUAL(504.0, linear.params.damping_ns_per_m, 0.0);
  const Scene stribeck = read_scene_file(dir + "stribeck-undamped.toml");
  CHECK_TRUE(stribeck.params.model == FrictionModel::stribeck);
  DOUBLES_EQUAL(0.0, stribeck.params.damping_ns_per_m, 0.0);  // no damper effect: b = 0
  const Scene stops = read_scene_file(dir + "seat-with-end-stops.toml");
  CHECK_TRUE(stops.effects & kEndStops);
  DOUBLES_EQUAL(0.05, stops.stops.travel_m, 0.0);
  DOUBLES_EQUAL(2e5, stops.stops.stiffness_n_per_m, 0.0);
  // The core model the scene dispatches to configures with these parameters.
  const SceneParams core = stops.core();
  const bool configured = with_scene_model<double>(
      core, [&](auto& model) { return configure_for_scene(model, core).ok(); });
  CHECK_TRUE(configured);
}

// The effects a scene names choose the cheapest model that has them all.
TEST(SceneFile, EffectsChooseTheModel) {
  const char* head = "[scene]\neffects = [";
  CHECK_TRUE(scene_of(std::string(head) + "\"spring\"]\n").params.model == FrictionModel::linear);
  CHECK_TRUE(scene_of(std::string(head) + "\"spring\", \"coulomb\"]\n").params.model ==
             FrictionModel::signum);
  CHECK_TRUE(scene_of(std::string(head) + "\"spring\", \"coulomb\", \"static_friction\"]\n")
                 .params.model == FrictionModel::stick_slip);
  const Scene smooth =
      scene_of(std::string(head) +
               "\"spring\", \"coulomb\"]\nmodel = \"smooth\"\n[seat]\nsmoothing = \"atan\"\n"
               "smoothing_constant_s_per_m = 300\nkinetic_friction_n = 20\n");
  CHECK_TRUE(smooth.params.model == FrictionModel::smooth);
  CHECK_TRUE(smooth.params.smoothing == SmoothingLaw::atan);
  DOUBLES_EQUAL(20.0, smooth.params.static_friction_n, 0.0);  // F_fs = F_fk without static friction
  CHECK_TRUE(smooth.model_given);
}

TEST(SceneFile, ContradictionsAndUnknownNamesAreErrorsWithLineAndKey) {
  STRCMP_CONTAINS("unknown effect 'viscous'",
                  error_of("[scene]\neffects = [\"spring\", \"viscous\"]\n").c_str());
  STRCMP_CONTAINS("needs its 'spring'", error_of("[scene]\neffects = [\"damper\"]\n").c_str());
  STRCMP_CONTAINS("needs an [end_stops] table",
                  error_of("[scene]\neffects = [\"spring\", \"end_stops\"]\n").c_str());
  STRCMP_CONTAINS(
      "no 'end_stops' effect",
      error_of("[scene]\neffects = [\"spring\"]\n[end_stops]\ntravel_m = 0.05\n").c_str());
  STRCMP_CONTAINS("'static_friction' needs 'coulomb'",
                  error_of("[scene]\neffects = [\"spring\", \"static_friction\"]\n").c_str());
  // A parameter for an effect the scene leaves out.
  const std::string damping =
      error_of("[scene]\neffects = [\"spring\"]\n[seat]\ndamping_ns_per_m = 504\n");
  STRCMP_CONTAINS(":4:", damping.c_str());
  STRCMP_CONTAINS("no 'damper' effect", damping.c_str());
  STRCMP_CONTAINS("does not model the scene's effects",
                  error_of("[scene]\neffects = [\"spring\"]\nmodel = \"stick-slip\"\n").c_str());
  STRCMP_CONTAINS("unknown key 'mass'",
                  error_of("[scene]\neffects = [\"spring\"]\n[seat]\nmass = 80\n").c_str());
  STRCMP_CONTAINS(
      "must be a number",
      error_of("[scene]\neffects = [\"spring\"]\n[seat]\nmass_kg = \"heavy\"\n").c_str());
  STRCMP_CONTAINS("11-bit CAN identifier",
                  error_of("[scene]\neffects = [\"spring\"]\n[can]\ninput_id = 0x800\n").c_str());
  STRCMP_CONTAINS("unknown integrator",
                  error_of("[scene]\neffects = [\"spring\"]\nintegrator = \"rk5\"\n").c_str());
  // Not TOML at all: the parser's own message with line and column.
  STRCMP_CONTAINS(":2:", error_of("[scene]\neffects = [\"spring\"\n").c_str());
  STRCMP_CONTAINS("missing table [scene]", error_of("[seat]\nmass_kg = 80\n").c_str());
}
