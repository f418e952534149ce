// Glue for deployfx/contact: normal force laws, regularised Coulomb friction and the 1-DOF
// impact. The typed API (kind names, broadcasting, result object) is python/deployfx/contact.py.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <vector>

#include "deployfx/contact/force_law.hpp"
#include "deployfx/contact/friction.hpp"
#include "deployfx/contact/impact.hpp"

namespace py = pybind11;
using deployfx::contact::ContactLaw;
using deployfx::contact::CoulombFriction;
using deployfx::contact::ImpactResult;

namespace {

using Array = Eigen::ArrayXd;
using ArrayIn = Eigen::Ref<const Eigen::ArrayXd>;

void require_same_size(const ArrayIn& a, const ArrayIn& b) {
  if (a.size() != b.size())
    throw std::invalid_argument("force_many: the arrays must have one size");
}

py::array_t<double> to_numpy(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

}  // namespace

void define_contact(py::module_& m) {
  py::class_<ContactLaw> law(m, "ContactLaw");
  py::enum_<ContactLaw::Kind>(law, "Kind")
      .value("kelvin_voigt_hertz", ContactLaw::Kind::kKelvinVoigtHertz)
      .value("hunt_crossley", ContactLaw::Kind::kHuntCrossley)
      .value("lankarani_nikravesh", ContactLaw::Kind::kLankaraniNikravesh)
      .value("flores", ContactLaw::Kind::kFlores);
  law.def(py::init<ContactLaw::Kind, double, double, double, double>(), py::arg("kind"),
          py::arg("K"), py::arg("n") = 1.5, py::arg("D") = 0.0, py::arg("e") = 1.0)
      .def_property_readonly("kind", &ContactLaw::kind)
      .def_property_readonly("K", &ContactLaw::K)
      .def_property_readonly("n", &ContactLaw::n)
      .def_property_readonly("D", &ContactLaw::D)
      .def_property_readonly("e", &ContactLaw::e)
      .def_property_readonly("hysteresis_factor", &ContactLaw::hysteresis_factor)
      .def_property_readonly("needs_onset_speed", &ContactLaw::needs_onset_speed)
      .def("force",
           [](const ContactLaw& l, double delta, double delta_dot, double v0) {
             const auto c = l.evaluate(delta, delta_dot, v0);
             return py::make_tuple(c.F, c.dF_ddelta, c.dF_ddelta_dot);
           },
           py::arg("delta"), py::arg("delta_dot"), py::arg("v0"))
      .def("force_many",
           [](const ContactLaw& l, const ArrayIn& delta, const ArrayIn& delta_dot,
              const ArrayIn& v0) {
             require_same_size(delta, delta_dot);
             require_same_size(delta, v0);
             Array F(delta.size()), dd(delta.size()), dv(delta.size());
             for (Eigen::Index i = 0; i < delta.size(); ++i) {
               const auto c = l.evaluate(delta[i], delta_dot[i], v0[i]);
               F[i] = c.F;
               dd[i] = c.dF_ddelta;
               dv[i] = c.dF_ddelta_dot;
             }
             return py::make_tuple(F, dd, dv);
           },
           py::arg("delta"), py::arg("delta_dot"), py::arg("v0"));

  py::class_<CoulombFriction>(m, "CoulombFriction")
      .def(py::init<double, double>(), py::arg("mu"), py::arg("v_reg") = 1e-4)
      .def_property_readonly("mu", &CoulombFriction::mu)
      .def_property_readonly("v_reg", &CoulombFriction::v_reg)
      .def("force",
           [](const CoulombFriction& fr, double v_t, double F_n) {
             const auto c = fr.evaluate(v_t, F_n);
             return py::make_tuple(c.F_t, c.dF_dv_t, c.dF_dF_n);
           },
           py::arg("v_t"), py::arg("F_n"))
      .def("force_many",
           [](const CoulombFriction& fr, const ArrayIn& v_t, const ArrayIn& F_n) {
             require_same_size(v_t, F_n);
             Array F(v_t.size()), dv(v_t.size()), dn(v_t.size());
             for (Eigen::Index i = 0; i < v_t.size(); ++i) {
               const auto c = fr.evaluate(v_t[i], F_n[i]);
               F[i] = c.F_t;
               dv[i] = c.dF_dv_t;
               dn[i] = c.dF_dF_n;
             }
             return py::make_tuple(F, dv, dn);
           },
           py::arg("v_t"), py::arg("F_n"));

  m.def("impact_time_scale", &deployfx::contact::impact_time_scale, py::arg("law"),
        py::arg("mass"), py::arg("v0"));
  m.def("simulate_impact",
        [](const ContactLaw& law, double mass, double v0, double dt, bool record, long max_steps) {
          ImpactResult r;
          {
            // Ctrl-C: the signal handler only sets a flag; check it with the GIL held.
            const auto poll = [] {
              py::gil_scoped_acquire acquire;
              if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            };
            py::gil_scoped_release release;
            r = deployfx::contact::simulate_impact(law, mass, v0, dt, record, max_steps, poll);
          }
          py::dict d;
          d["restitution"] = r.restitution;
          d["max_penetration"] = r.max_penetration;
          d["contact_duration"] = r.contact_duration;
          d["peak_force"] = r.peak_force;
          d["energy_lost"] = r.energy_lost;
          d["steps"] = r.steps;
          d["t"] = to_numpy(r.t);
          d["delta"] = to_numpy(r.delta);
          d["delta_dot"] = to_numpy(r.delta_dot);
          d["force"] = to_numpy(r.force);
          return d;
        },
        py::arg("law"), py::arg("mass"), py::arg("v0"), py::arg("dt"), py::arg("record") = false,
        py::arg("max_steps") = 10'000'000L);
}
