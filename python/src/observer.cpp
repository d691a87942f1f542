// The observer (double), for the model the parameters and the scene name (end stops included).
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <type_traits>

#include "module.hpp"
#include "stickslip/models/scene.hpp"
#include "stickslip/observer/observer.hpp"

namespace stickslip::python {
namespace {

struct Estimate {
  Sample model;
  bool measured = false;
  double residual = 0.0, measured_friction = 0.0;
};

class AnyObserver {
 public:
  virtual ~AnyObserver() = default;
  virtual void reset(double a_u0, double x0_m, double v0_m_per_s) = 0;
  virtual Estimate update(double a_u) = 0;
  virtual Estimate update(double a_u, double a_x_measured) = 0;
  virtual ObserverSummary summary() const = 0;
  virtual std::uint64_t samples() const = 0;
  virtual double seat_weighted_rms() const = 0;
  virtual double seat_vdv() const = 0;
};

// kEndStops: the observer of the seat with end stops (the scene's stops).
template <typename Law, bool kEndStops>
class ObserverOf final : public AnyObserver {
 public:
  Observer<double, Law, 10, true, kEndStops> observer;
  void reset(double a_u0, double x0_m, double v0_m_per_s) override {
    observer.reset(a_u0, x0_m, v0_m_per_s);
  }
  Estimate update(double a_u) override { return estimate_of(observer.update(a_u)); }
  Estimate update(double a_u, double a_x_measured) override {
    return estimate_of(observer.update(a_u, a_x_measured));
  }
  ObserverSummary summary() const override { return observer.summary(); }
  std::uint64_t samples() const override { return observer.samples(); }
  double seat_weighted_rms() const override { return observer.comfort().seat_weighted_rms(); }
  double seat_vdv() const override { return observer.comfort().seat_vdv(); }

 private:
  static Estimate estimate_of(const ObserverEstimate<double>& e) {
    return {sample_of(e.model), e.measured, e.residual_m_per_s2, e.measured_friction_n};
  }
};

class PyObserver {
 public:
  PyObserver(double dt_s, const py::dict& options, double window_s, double exponential_time_s,
             double regime_hysteresis_k, double mismatch_rms) {
    const RunSpec spec = parse_spec(options);
    if (spec.scalar != ScalarType::float64 || spec.setup.reference) {
      throw HostError(
          "Observer runs the core's oscillator in double (with the scene's end stops), not the "
          "reference solver");
    }
    ObserverParams params;
    params.model = spec.setup.params;
    params.model.dt_s = dt_s;
    params.stops = spec.setup.stops;
    params.window_s = window_s;
    params.exponential_time_s = exponential_time_s;
    params.regime_hysteresis_k = regime_hysteresis_k;
    params.mismatch_rms_m_per_s2 = mismatch_rms;
    // The model type the scene names (models/scene.hpp), as Oscillator and simulate() choose it.
    const SceneParams scene{spec.setup.effects, params.model, params.stops};
    with_scene_model<double>(scene, [&](auto& prototype) {
      using Model = std::decay_t<decltype(prototype)>;
      using Law = typename Model::FrictionLaw;
      constexpr bool kEndStops = std::is_same_v<Model, EndStopOscillator<double, Law>>;
      auto made = std::make_unique<ObserverOf<Law, kEndStops>>();
      const ConfigResult configured = made->observer.configure(params);
      if (!configured.ok())
        throw HostError(explain_configuration_error(configured.message.c_str()));
      observer_ = std::move(made);
    });
    observer_->reset(0.0, spec.setup.x0_m, spec.setup.v0_m_per_s);
  }
  AnyObserver& get() { return *observer_; }
  const AnyObserver& get() const { return *observer_; }

 private:
  std::unique_ptr<AnyObserver> observer_;
};

py::dict summary_dict(const AnyObserver& observer) {
  const ObserverSummary s = observer.summary();
  py::dict d;
  d["samples"] = observer.samples();
  d["rms_u"] = s.rms_u_m_per_s2;
  d["rms_x"] = s.rms_x_m_per_s2;
  d["T_ax"] = s.transmissibility;
  d["p_stick"] = s.stick_probability;
  d["K"] = s.den_hartog_k;
  d["stick_events"] = s.stick_events;
  d["slip_events"] = s.slip_events;
  d["window_s"] = s.window_s;
  d["window_full"] = s.window_full;
  d["exp_rms_u"] = s.exp_rms_u_m_per_s2;
  d["exp_rms_x"] = s.exp_rms_x_m_per_s2;
  d["exp_T_ax"] = s.exp_transmissibility;
  d["exp_p_stick"] = s.exp_stick_probability;
  d["exp_K"] = s.exp_den_hartog_k;
  d["regime"] = s.regime_known ? py::object(py::str(regime_name(s.regime))) : py::none();
  d["regime_changes"] = s.regime_changes;
  d["residual_rms"] = s.residual_rms_m_per_s2;
  d["model_mismatch"] = s.model_mismatch;
  d["seat_weighted_rms"] = observer.seat_weighted_rms();
  d["vdv"] = observer.seat_vdv();
  return d;
}

}  // namespace

void bind_observer(py::module_& m) {
  py::class_<Estimate>(m, "Estimate", "One observer update")
      .def_readonly("model", &Estimate::model)
      .def_readonly("measured", &Estimate::measured)
      .def_readonly("residual", &Estimate::residual)
      .def_readonly("measured_friction", &Estimate::measured_friction);

  py::class_<PyObserver>(m, "Observer")
      .def(py::init<double, const py::dict&, double, double, double, double>(), py::arg("dt"),
           py::arg("options"), py::arg("window_s") = 10.0, py::arg("exponential_time_s") = 10.0,
           py::arg("regime_hysteresis_k") = 0.05, py::arg("mismatch_rms") = 0.1)
      .def(
          "reset",
          [](PyObserver& o, double a_u0, double x0, double v0) { o.get().reset(a_u0, x0, v0); },
          py::arg("a_u0") = 0.0, py::arg("x0") = 0.0, py::arg("v0") = 0.0)
      .def(
          "update",
          [](PyObserver& o, double a_u, std::optional<double> a_x_measured) {
            return a_x_measured ? o.get().update(a_u, *a_x_measured) : o.get().update(a_u);
          },
          py::arg("a_u"), py::arg("a_x_measured") = py::none())
      .def("summary", [](const PyObserver& o) { return summary_dict(o.get()); });
}

}  // namespace stickslip::python
