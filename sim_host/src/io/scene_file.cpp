#include "stickslip/host/io/scene_file.hpp"

#include <cmath>
#include <string_view>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

std::string where(const std::string& path, const toml::source_region& region) {
  return path + ":" + std::to_string(region.begin.line) + ":" + std::to_string(region.begin.column);
}

[[noreturn]] void fail(const std::string& path, const toml::node& node, const std::string& what) {
  throw HostError(where(path, node.source()) + ": " + what);
}

struct EffectName {
  const char* name;
  SceneEffect bit;
};
constexpr EffectName kEffects[] = {{"spring", kSpring},     {"damper", kDamper},
                                   {"coulomb", kCoulomb},   {"static_friction", kStaticFriction},
                                   {"stribeck", kStribeck}, {"end_stops", kEndStops}};

void only_keys(const std::string& path, const toml::table& table, std::string_view table_name,
               std::initializer_list<std::string_view> allowed) {
  for (const auto& [key, node] : table) {
    bool known = false;
    for (std::string_view a : allowed) known = known || key.str() == a;
    if (!known) {
      fail(path, node,
           "unknown key '" + std::string(key.str()) + "' in [" + std::string(table_name) + "]");
    }
  }
}

// A finite number (integer or float) at table[key], if present.
std::optional<double> number(const std::string& path, const toml::table& table,
                             std::string_view key) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return std::nullopt;
  double value = 0.0;
  if (const auto* i = node->as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node->as_floating_point()) {
    value = f->get();
  } else {
    fail(path, *node, "'" + std::string(key) + "' must be a number");
  }
  if (!std::isfinite(value)) fail(path, *node, "'" + std::string(key) + "' must be finite");
  return value;
}

std::optional<std::string> text(const std::string& path, const toml::table& table,
                                std::string_view key) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* s = node->as_string();
  if (s == nullptr) fail(path, *node, "'" + std::string(key) + "' must be a string");
  return s->get();
}

std::optional<std::uint32_t> can_id(const std::string& path, const toml::table& table,
                                    std::string_view key) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* i = node->as_integer();
  if (i == nullptr || i->get() < 0 || i->get() > 0x7FF) {
    fail(path, *node, "'" + std::string(key) + "' must be an 11-bit CAN identifier (0 .. 0x7FF)");
  }
  return static_cast<std::uint32_t>(i->get());
}

// [scene] effects: the bits, each named once, in a combination the core models.
const toml::node& read_effects(const std::string& path, const toml::table& scene_table,
                               Scene& scene) {
  const toml::node* effects_node = scene_table.get("effects");
  if (effects_node == nullptr)
    throw HostError(where(path, scene_table.source()) + ": [scene] needs 'effects'");
  const toml::array* effects = effects_node->as_array();
  if (effects == nullptr) fail(path, *effects_node, "'effects' must be an array of effect names");
  for (const toml::node& e : *effects) {
    const auto* name = e.as_string();
    if (name == nullptr) fail(path, e, "an effect must be a string");
    unsigned bit = 0;
    for (const EffectName& known : kEffects)
      if (name->get() == known.name) bit = known.bit;
    if (bit == 0) {
      fail(path, e,
           "unknown effect '" + name->get() +
               "' (spring, damper, coulomb, static_friction, stribeck, end_stops)");
    }
    if (scene.effects & bit) fail(path, e, "effect '" + name->get() + "' named twice");
    scene.effects |= bit;
  }
  if ((scene.effects & kSpring) == 0) {
    fail(path, *effects_node,
         "a seat needs its 'spring' (the core models a suspended seat, k > 0)");
  }
  if ((scene.effects & kStaticFriction) && !(scene.effects & kCoulomb)) {
    fail(path, *effects_node, "'static_friction' needs 'coulomb' (F_fs >= F_fk)");
  }
  if ((scene.effects & kStribeck) && !(scene.effects & kStaticFriction)) {
    fail(path, *effects_node, "'stribeck' needs 'static_friction' and 'coulomb'");
  }

  return *effects_node;
}

// [scene] model, integrator and sample rate, checked against the effects.
void read_scene_model(const std::string& path, const toml::table& scene_table, Scene& scene) {
  OscillatorParams& p = scene.params;
  p.damping_ns_per_m = 0.0;
  p.kinetic_friction_n = p.static_friction_n = 0.0;
  p.model = model_for_effects(scene.effects);
  p.integrator = default_integrator(p.model);
  if (const auto model = text(path, scene_table, "model")) {
    FrictionModel parsed;
    if (!parse_model(model->c_str(), parsed))
      fail(path, *scene_table.get("model"), "unknown model '" + *model + "'");
    const bool needs_friction = parsed != FrictionModel::linear;
    const bool has_friction = (scene.effects & kCoulomb) != 0;
    if (needs_friction != has_friction ||
        ((parsed == FrictionModel::stick_slip || parsed == FrictionModel::stribeck) &&
         !(scene.effects & kStaticFriction)) ||
        (parsed == FrictionModel::stribeck) != ((scene.effects & kStribeck) != 0)) {
      fail(path, *scene_table.get("model"),
           "model '" + *model + "' does not model the scene's effects (they need '" +
               model_name(model_for_effects(scene.effects)) + "')");
    }
    p.model = parsed;
    p.integrator = default_integrator(parsed);
    scene.model_given = true;
  }
  if (const auto integrator = text(path, scene_table, "integrator")) {
    if (!parse_integrator(integrator->c_str(), p.integrator)) {
      fail(path, *scene_table.get("integrator"), "unknown integrator '" + *integrator + "'");
    }
    scene.integrator_given = true;
  }
  if (const auto rate = number(path, scene_table, "sample_rate_hz")) {
    if (!(*rate > 0.0))
      fail(path, *scene_table.get("sample_rate_hz"), "'sample_rate_hz' must be > 0");
    scene.sample_rate_hz = *rate;
    p.dt_s = 1.0 / *rate;
  }
}

// [seat]: the parameters, each only with the effect it belongs to.
void read_seat(const std::string& path, const toml::table& root, Scene& scene) {
  OscillatorParams& p = scene.params;
  if (const toml::table* seat = root["seat"].as_table()) {
    only_keys(path, *seat, "seat",
              {"mass_kg", "stiffness_n_per_m", "damping_ns_per_m", "kinetic_friction_n",
               "static_friction_n", "stribeck_velocity_m_per_s", "smoothing",
               "smoothing_constant_s_per_m"});
    // A parameter of an effect the scene leaves out is a contradiction, not a default.
    const auto requires_effect = [&](std::string_view key, unsigned effect,
                                     const char* effect_name) {
      const toml::node* node = seat->get(key);
      if (node != nullptr && (scene.effects & effect) == 0) {
        fail(path, *node,
             "'" + std::string(key) + "' given but the scene has no '" + effect_name + "' effect");
      }
    };
    requires_effect("damping_ns_per_m", kDamper, "damper");
    requires_effect("kinetic_friction_n", kCoulomb, "coulomb");
    requires_effect("static_friction_n", kStaticFriction, "static_friction");
    requires_effect("stribeck_velocity_m_per_s", kStribeck, "stribeck");
    if (p.model != FrictionModel::smooth) {
      for (const char* key : {"smoothing", "smoothing_constant_s_per_m"}) {
        if (const toml::node* node = seat->get(key))
          fail(path, *node, std::string("'") + key + "' given but the model is not 'smooth'");
      }
    }
    if (auto v = number(path, *seat, "mass_kg")) p.mass_kg = *v;
    if (auto v = number(path, *seat, "stiffness_n_per_m")) p.stiffness_n_per_m = *v;
    if (auto v = number(path, *seat, "damping_ns_per_m")) p.damping_ns_per_m = *v;
    if (auto v = number(path, *seat, "kinetic_friction_n")) p.kinetic_friction_n = *v;
    if (auto v = number(path, *seat, "static_friction_n")) p.static_friction_n = *v;
    if (auto v = number(path, *seat, "stribeck_velocity_m_per_s")) p.stribeck_velocity_m_per_s = *v;
    if (auto v = number(path, *seat, "smoothing_constant_s_per_m"))
      p.smoothing_constant_s_per_m = *v;
    if (auto v = text(path, *seat, "smoothing")) {
      if (!parse_smoothing(v->c_str(), p.smoothing))
        fail(path, *seat->get("smoothing"), "unknown smoothing '" + *v + "'");
    }
  } else if (root.contains("seat")) {
    fail(path, *root.get("seat"), "[seat] must be a table");
  }
}

// [end_stops], required exactly with the end_stops effect.
void read_end_stops(const std::string& path, const toml::table& root,
                    const toml::node& effects_node, Scene& scene) {
  OscillatorParams& p = scene.params;
  if (const toml::table* stops = root["end_stops"].as_table()) {
    if ((scene.effects & kEndStops) == 0)
      fail(path, *stops, "[end_stops] given but the scene has no 'end_stops' effect");
    only_keys(path, *stops, "end_stops", {"travel_m", "stiffness_n_per_m", "damping_ns_per_m"});
    const auto required = [&](std::string_view key) {
      const auto v = number(path, *stops, key);
      if (!v) fail(path, *stops, "[end_stops] needs '" + std::string(key) + "'");
      return *v;
    };
    scene.stops.travel_m = required("travel_m");
    scene.stops.stiffness_n_per_m = required("stiffness_n_per_m");
    scene.stops.damping_ns_per_m = number(path, *stops, "damping_ns_per_m").value_or(0.0);
  } else if (scene.effects & kEndStops) {
    fail(path, effects_node,
         "effect 'end_stops' needs an [end_stops] table (travel_m, stiffness_n_per_m)");
  }
  if ((scene.effects & kEndStops) && p.model != FrictionModel::linear &&
      p.model != FrictionModel::stick_slip && p.model != FrictionModel::stribeck) {
    fail(path, effects_node,
         std::string("end stops run with no friction, stick-slip or stribeck, not '") +
             model_name(p.model) + "'");
  }
  if (scene.effects & kEndStops) p.integrator = Integrator::exact;  // the end-stop model's only one
}

// [can]: the identifiers the scene expects on the bus.
void read_can(const std::string& path, const toml::table& root, Scene& scene) {
  if (const toml::table* can = root["can"].as_table()) {
    only_keys(path, *can, "can", {"input_id", "output_id"});
    scene.can.input_id = can_id(path, *can, "input_id");
    scene.can.output_id = can_id(path, *can, "output_id");
  } else if (root.contains("can")) {
    fail(path, *root.get("can"), "[can] must be a table");
  }
}

}  // namespace

Scene read_scene_file(const std::string& path) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw HostError(where(path, e.source()) + ": " + std::string(e.description()));
  }
  only_keys(path, root, "top level", {"scene", "seat", "end_stops", "can"});
  const toml::table* scene_table = root["scene"].as_table();
  if (scene_table == nullptr) throw HostError(path + ": missing table [scene]");
  only_keys(path, *scene_table, "scene",
            {"name", "effects", "model", "integrator", "sample_rate_hz"});

  Scene scene;
  scene.name = text(path, *scene_table, "name").value_or("");
  const toml::node& effects_node = read_effects(path, *scene_table, scene);
  read_scene_model(path, *scene_table, scene);
  read_seat(path, root, scene);
  // Coulomb without static friction: F_fs = F_fk (what the signum and smooth laws assume anyway).
  if ((scene.effects & kStaticFriction) == 0)
    scene.params.static_friction_n = scene.params.kinetic_friction_n;
  read_end_stops(path, root, effects_node, scene);
  read_can(path, root, scene);
  return scene;
}

}  // namespace stickslip::host
