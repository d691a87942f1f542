// The core's oscillator, sample by sample: the model type the scene names, chosen once; with an
// actuator force (N) when one is given, through the core's own step(a_u, f_a).
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

#include "module.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::python {
namespace {

class AnySeat {
 public:
  virtual ~AnySeat() = default;
  virtual void reset(double x0_m, double v0_m_per_s, double a_u0) = 0;
  virtual void reset(double x0_m, double v0_m_per_s, double a_u0, double f_a0_n) = 0;
  virtual Sample step(double a_u) = 0;
  virtual Sample step(double a_u, double f_a_n) = 0;
  virtual Sample current() const = 0;
  virtual Sample current_with_force(double f_a_n) const = 0;
  // step() for every sample of a_u (with f_a[i] when f_a is not null), the outputs into the
  // arrays (n samples each).
  virtual void run(const double* a_u, const double* f_a, std::size_t n, double* x_r, double* v_r,
                   double* a_x, double* f_f, std::uint8_t* stuck) = 0;
  virtual std::uint64_t rejected_inputs() const = 0;
  virtual std::uint64_t event_budget_exhausted() const = 0;
  virtual std::uint64_t state_resets() const = 0;
};

template <typename T, typename Model>
class SeatOf final : public AnySeat {
 public:
  Model model;
  void reset(double x0_m, double v0_m_per_s, double a_u0) override {
    model.reset(static_cast<T>(x0_m), static_cast<T>(v0_m_per_s), static_cast<T>(a_u0));
  }
  void reset(double x0_m, double v0_m_per_s, double a_u0, double f_a0_n) override {
    model.reset(static_cast<T>(x0_m), static_cast<T>(v0_m_per_s), static_cast<T>(a_u0),
                static_cast<T>(f_a0_n));
  }
  Sample step(double a_u) override { return sample_of(model.step(static_cast<T>(a_u))); }
  Sample step(double a_u, double f_a_n) override {
    return sample_of(model.step(static_cast<T>(a_u), static_cast<T>(f_a_n)));
  }
  Sample current() const override { return sample_of(model.current()); }
  Sample current_with_force(double f_a_n) const override {
    return sample_of(model.current_with_force(static_cast<T>(f_a_n)));
  }
  void run(const double* a_u, const double* f_a, std::size_t n, double* x_r, double* v_r,
           double* a_x, double* f_f, std::uint8_t* stuck) override {
    for (std::size_t i = 0; i < n; ++i) {
      // Without a force, the plain step(a_u) that simulate() runs for a recording without one.
      const StepOutput<T> out = f_a != nullptr
                                    ? model.step(static_cast<T>(a_u[i]), static_cast<T>(f_a[i]))
                                    : model.step(static_cast<T>(a_u[i]));
      x_r[i] = static_cast<double>(out.x_r_m);
      v_r[i] = static_cast<double>(out.v_r_m_per_s);
      a_x[i] = static_cast<double>(out.a_x_m_per_s2);
      f_f[i] = static_cast<double>(out.friction_n);
      stuck[i] = out.stuck ? 1 : 0;
    }
  }
  std::uint64_t rejected_inputs() const override { return model.rejected_inputs(); }
  std::uint64_t event_budget_exhausted() const override { return model.event_budget_exhausted(); }
  std::uint64_t state_resets() const override { return model.state_resets(); }
};

template <typename T>
std::unique_ptr<AnySeat> make_seat(const SceneParams& scene) {
  std::unique_ptr<AnySeat> seat;
  with_scene_model<T>(scene, [&](auto& prototype) {
    using Model = std::decay_t<decltype(prototype)>;
    auto made = std::make_unique<SeatOf<T, Model>>();
    const ConfigResult configured = configure_for_scene(made->model, scene);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    seat = std::move(made);
  });
  return seat;
}

class PyOscillator {
 public:
  PyOscillator(double dt_s, const py::dict& options) : spec_(parse_spec(options)) {
    if (spec_.setup.reference) {
      throw HostError("integrator: 'reference' is the host's whole-signal solver; use simulate()");
    }
    if (spec_.scalar != ScalarType::float64 && spec_.scalar != ScalarType::float32) {
      throw HostError(std::string("scalar: Oscillator runs 'double' or 'float', not '") +
                      host::scalar_name(spec_.scalar) + "'; use simulate() for fixed point");
    }
    spec_.setup.params.dt_s = dt_s;
    const SceneParams scene{spec_.setup.effects, spec_.setup.params, spec_.setup.stops};
    try {
      seat_ =
          spec_.scalar == ScalarType::float32 ? make_seat<float>(scene) : make_seat<double>(scene);
    } catch (const ConfigurationError& error) {
      throw HostError(explain_configuration_error(error.what()));
    }
    seat_->reset(spec_.setup.x0_m, spec_.setup.v0_m_per_s, 0.0);
  }

  // With f_a (N) the core's actuated calls, as simulate() makes them for a force column: reset
  // with f_a[0], row 0 current(f_a[0]), then step(a_u[n], f_a[n]).
  void reset(double x0_m, double v0_m_per_s, double a_u0, std::optional<double> f_a0_n) {
    if (f_a0_n) {
      seat_->reset(x0_m, v0_m_per_s, a_u0, *f_a0_n);
    } else {
      seat_->reset(x0_m, v0_m_per_s, a_u0);
    }
  }
  Sample step(double a_u, std::optional<double> f_a_n) {
    return f_a_n ? seat_->step(a_u, *f_a_n) : seat_->step(a_u);
  }
  Sample current(std::optional<double> f_a_n) const {
    return f_a_n ? seat_->current_with_force(*f_a_n) : seat_->current();
  }

  // Steps over a whole array: the input read in place (contiguous float64; other arrays are
  // converted once), the outputs written straight into new numpy arrays, the GIL released.
  py::dict run(
      const py::array_t<double, py::array::c_style | py::array::forcecast>& a_u,
      const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& f_a) {
    if (a_u.ndim() != 1) throw HostError("a_u: expected a 1-D array of samples");
    const py::ssize_t n = a_u.shape(0);
    if (f_a && (f_a->ndim() != 1 || f_a->shape(0) != n)) {
      throw HostError("f_a: expected a 1-D array of forces (N), one per sample of a_u");
    }
    const double* force = f_a ? f_a->data() : nullptr;
    py::array_t<double> x_r(n), v_r(n), a_x(n), f_f(n);
    py::array_t<bool> stuck(n);
    static_assert(sizeof(bool) == sizeof(std::uint8_t), "numpy's bool is one byte");
    {
      py::gil_scoped_release release;
      seat_->run(a_u.data(), force, static_cast<std::size_t>(n), x_r.mutable_data(),
                 v_r.mutable_data(), a_x.mutable_data(), f_f.mutable_data(),
                 reinterpret_cast<std::uint8_t*>(stuck.mutable_data()));
    }
    py::dict trace;
    trace["x_r"] = x_r;
    trace["v_r"] = v_r;
    trace["a_x"] = a_x;
    trace["f_f"] = f_f;
    trace["stuck"] = stuck;
    return trace;
  }

  const RunSpec& spec() const { return spec_; }
  const AnySeat& seat() const { return *seat_; }

 private:
  RunSpec spec_;
  std::unique_ptr<AnySeat> seat_;
};

}  // namespace

void bind_oscillator(py::module_& m) {
  namespace host = stickslip::host;
  py::class_<Sample>(m, "Step", "One step's output (SI units)")
      .def_readonly("x_r", &Sample::x_r)
      .def_readonly("v_r", &Sample::v_r)
      .def_readonly("a_x", &Sample::a_x)
      .def_readonly("f_f", &Sample::f_f)
      .def_readonly("stuck", &Sample::stuck)
      .def_readonly("stuck_time", &Sample::stuck_time)
      .def_readonly("stuck_fraction", &Sample::stuck_fraction)
      .def_readonly("events", &Sample::events)
      .def("__repr__", [](const Sample& s) {
        return "Step(x_r=" + format_number(s.x_r) + ", v_r=" + format_number(s.v_r) +
               ", a_x=" + format_number(s.a_x) + ", f_f=" + format_number(s.f_f) +
               ", stuck=" + (s.stuck ? "True" : "False") + ")";
      });

  py::class_<PyOscillator>(m, "Oscillator")
      .def(py::init<double, const py::dict&>(), py::arg("dt"), py::arg("options"))
      .def("reset", &PyOscillator::reset, py::arg("x0") = 0.0, py::arg("v0") = 0.0,
           py::arg("a_u0") = 0.0, py::arg("f_a0") = py::none())
      .def("step", &PyOscillator::step, py::arg("a_u"), py::arg("f_a") = py::none())
      .def("current", &PyOscillator::current, py::arg("f_a") = py::none())
      .def("run", &PyOscillator::run, py::arg("a_u"), py::arg("f_a") = py::none())
      .def_property_readonly("dt", [](const PyOscillator& o) { return o.spec().setup.params.dt_s; })
      .def_property_readonly(
          "model",
          [](const PyOscillator& o) { return stickslip::model_name(o.spec().setup.params.model); })
      .def_property_readonly("integrator",
                             [](const PyOscillator& o) {
                               return stickslip::integrator_name(o.spec().setup.params.integrator);
                             })
      .def_property_readonly(
          "scalar", [](const PyOscillator& o) { return host::scalar_name(o.spec().scalar); })
      .def_property_readonly("rejected_inputs",
                             [](const PyOscillator& o) { return o.seat().rejected_inputs(); })
      .def_property_readonly(
          "event_budget_exhausted",
          [](const PyOscillator& o) { return o.seat().event_budget_exhausted(); })
      .def_property_readonly("state_resets",
                             [](const PyOscillator& o) { return o.seat().state_resets(); });
}

}  // namespace stickslip::python
