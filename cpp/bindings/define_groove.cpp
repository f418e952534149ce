// Glue for the pin-groove lock: contact/groove_profile (elements, chain, pin queries),
// joint/latch_follower, joint/pin_groove and joint/lock_profiles; and today's joint::lock_load
// as a reference for the tests. The typed API is python/deployfx/groove.py.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deployfx/contact/groove_profile.hpp"
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/joint/latch_follower.hpp"
#include "deployfx/joint/lock_profiles.hpp"
#include "deployfx/joint/pin_groove.hpp"

namespace py = pybind11;
using deployfx::contact::ContactLaw;
using deployfx::contact::CoulombFriction;
using deployfx::contact::GrooveElement;
using deployfx::contact::GrooveProfile;
using deployfx::contact::PinQuery;
using namespace deployfx::joint;

namespace {

py::dict query_dict(const PinQuery& q) {
  py::dict d;
  d["in_range"] = q.in_range;
  d["gap"] = q.gap;
  d["point"] = q.point;
  d["n"] = q.n;
  d["t"] = q.t;
  d["dn_dc"] = q.dn_dc;
  d["facet"] = q.facet;
  d["element"] = q.element;
  d["at_vertex"] = q.at_vertex;
  d["chain_length"] = q.chain_length;
  return d;
}

py::dict wall_dict(const WallState& w) {
  py::dict d;
  d["contact"] = w.contact;
  d["F"] = w.F;
  d["delta"] = w.delta;
  d["delta_dot"] = w.delta_dot;
  return d;
}

void check_facet(const PinGrooveSpec& s, int facet) {
  if (facet < 0 || facet >= s.profile.num_facets())
    throw std::invalid_argument("facet = " + std::to_string(facet) + " is out of range: must be in [0, " +
                                std::to_string(s.profile.num_facets() - 1) + "]");
}

py::dict load_dict(const PinGrooveLoad& l) {
  py::dict d;
  d["torque"] = l.torque;
  d["d_theta"] = l.d_theta;
  d["d_rate"] = l.d_rate;
  d["normal_force"] = l.normal_force;
  d["support_force"] = l.support_force;
  d["pin_position"] = l.pin_position;
  d["support_lost"] = l.support_lost;
  return d;
}

}  // namespace

void define_groove(py::module_& m) {
  py::class_<GrooveElement>(m, "GrooveElement", "A segment or circular arc of a groove profile (contact/groove_profile.hpp).")
      .def_static("line", &GrooveElement::line, py::arg("start"), py::arg("end"))
      .def_static("arc", &GrooveElement::arc, py::arg("start"), py::arg("end"), py::arg("radius"))
      .def_static("arc_about", &GrooveElement::arc_about, py::arg("start"), py::arg("end"), py::arg("centre"),
                  py::arg("ccw"))
      .def_property_readonly("is_arc", [](const GrooveElement& e) { return e.kind() == GrooveElement::Kind::kArc; })
      .def_property_readonly("start", &GrooveElement::start)
      .def_property_readonly("end", &GrooveElement::end)
      .def_property_readonly("centre", &GrooveElement::centre)
      .def_property_readonly("radius", &GrooveElement::radius)
      .def_property_readonly("sweep", &GrooveElement::sweep)
      .def_property_readonly("length", &GrooveElement::length)
      .def("point", &GrooveElement::point, py::arg("u"))
      .def("tangent", &GrooveElement::tangent, py::arg("u"));

  py::class_<GrooveProfile>(m, "GrooveProfile", "A chain of groove elements split into facets (contact/groove_profile.hpp).")
      .def(py::init<std::vector<GrooveElement>>(), py::arg("elements"))
      .def_property_readonly("num_elements", &GrooveProfile::num_elements)
      .def_property_readonly("num_facets", &GrooveProfile::num_facets)
      .def_property_readonly("closed", &GrooveProfile::closed)
      .def("element", &GrooveProfile::element, py::arg("k"))
      .def("facet_elements", [](const GrooveProfile& p, int f) {
             if (f < 0 || f >= p.num_facets()) throw std::invalid_argument("facet out of range");
             return py::make_tuple(p.facet_first(f), p.facet_count(f));
           }, py::arg("facet"))
      .def("facet_of_element", &GrooveProfile::facet_of_element, py::arg("k"))
      .def("turn", &GrooveProfile::turn, py::arg("k"))
      .def("query", [](const GrooveProfile& p, int f, const Eigen::Vector2d& c, double rho) {
             return query_dict(p.query(f, c, rho));
           }, py::arg("facet"), py::arg("c"), py::arg("rho"))
      .def("closest", [](const GrooveProfile& p, const Eigen::Vector2d& c, double rho) {
             return query_dict(p.closest(c, rho));
           }, py::arg("c"), py::arg("rho"))
      .def("segment_distance", [](const GrooveProfile& p, int f, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
             const auto s = p.segment_distance(f, p0, p1);
             return py::make_tuple(s.distance, s.param);
           }, py::arg("facet"), py::arg("p0"), py::arg("p1"));

  py::class_<LatchSpring>(m, "LatchSpring", "A latch pin's spring (joint/latch_follower.hpp).")
      .def(py::init([](bool toward_axis, double stop, double travel, double preload, double stiffness) {
             LatchSpring l{toward_axis, stop, travel, preload, stiffness};
             l.validate();
             return l;
           }),
           py::kw_only(), py::arg("toward_axis") = true, py::arg("stop"), py::arg("travel"), py::arg("preload"),
           py::arg("stiffness"))
      .def_readonly("toward_axis", &LatchSpring::toward_axis)
      .def_readonly("stop", &LatchSpring::stop)
      .def_readonly("travel", &LatchSpring::travel)
      .def_readonly("preload", &LatchSpring::preload)
      .def_readonly("stiffness", &LatchSpring::stiffness);

  py::class_<PinGrooveSpec>(m, "PinGrooveSpec", "A pin against a groove profile on a hinge (joint/pin_groove.hpp).")
      .def(py::init<GrooveProfile, double, double, double, ContactLaw, CoulombFriction, std::optional<LatchSpring>>(),
           py::kw_only(), py::arg("profile"), py::arg("pin_distance"), py::arg("pin_angle"), py::arg("pin_radius"),
           py::arg("law"), py::arg("friction"), py::arg("latch") = std::nullopt)
      .def_readonly("profile", &PinGrooveSpec::profile)
      .def_readonly("pin_distance", &PinGrooveSpec::pin_distance)
      .def_readonly("pin_angle", &PinGrooveSpec::pin_angle)
      .def_readonly("pin_radius", &PinGrooveSpec::pin_radius)
      .def_readonly("latch", &PinGrooveSpec::latch);

  py::class_<FacetContact>(m, "FacetContact", "One facet's contact mode (joint/pin_groove.hpp).")
      .def(py::init<>())
      .def_readwrite("armed", &FacetContact::armed, "The pin has been on the facet's free side since it last left its range.")
      .def_readwrite("closed", &FacetContact::closed, "In contact: the law is used without its clamp.")
      .def_readwrite("inside", &FacetContact::inside, "Open, but within the compliant layer at the last accepted state.")
      .def_readwrite("v0", &FacetContact::v0, "Approach speed at onset, m/s (at least 1 mm/s).")
      .def_readwrite("T", &FacetContact::T, "Impact time scale of the contact in progress, s (set by the engine).")
      .def_readwrite("resolution", &FacetContact::resolution,
                     "The fraction of v0 T a step's local error may make while the contact lasts (set with T).");

  py::class_<PinGrooveHistory>(m, "PinGrooveHistory", "What a pin-groove lock remembers between steps.")
      .def(py::init<>())
      .def_readwrite("facets", &PinGrooveHistory::facets,
                     "One FacetContact per profile facet (a copy: assign the whole list to change it).")
      .def_readwrite("support", &PinGrooveHistory::support,
                     "Latch spring: the facet the pin rests on (-1: its bore stop).");

  m.def("groove_start_history", &start_history, py::arg("spec"), py::arg("theta"));
  m.def("groove_pin_position", [](const PinGrooveSpec& s, const PinGrooveHistory& h, double theta) {
          const auto st = pin_position(s, h, theta);
          py::dict d;
          d["found"] = st.found;
          d["beyond"] = st.beyond;
          d["bottomed"] = st.bottomed;
          d["w"] = st.w;
          d["s"] = st.s;
          d["ds"] = st.ds;
          d["d2s"] = st.d2s;
          d["drop_margin"] = st.drop_margin;
          return d;
        }, py::arg("spec"), py::arg("history"), py::arg("theta"));
  m.def("groove_load", [](const PinGrooveSpec& s, const PinGrooveHistory& h, double theta, double rate) {
          return load_dict(pin_groove_load(s, h, theta, rate));
        }, py::arg("spec"), py::arg("history"), py::arg("theta"), py::arg("rate"));
  m.def("groove_num_events", &num_events, py::arg("spec"));
  m.def("groove_facet_state", [](const PinGrooveSpec& s, const PinGrooveHistory& h, int facet, double theta,
                                 double rate) {
          check_facet(s, facet);
          return wall_dict(facet_state(s, h, facet, theta, rate));
        }, py::arg("spec"), py::arg("history"), py::arg("facet"), py::arg("theta"), py::arg("rate"));
  m.def("groove_facet_lever", [](const PinGrooveSpec& s, const PinGrooveHistory& h, int facet, double theta) {
          check_facet(s, facet);
          return facet_lever(s, h, facet, theta);
        }, py::arg("spec"), py::arg("history"), py::arg("facet"), py::arg("theta"));
  m.def("groove_contact_resolution", [](const PinGrooveSpec& s, const PinGrooveHistory& h, double theta) {
          const auto r = contact_resolution(s, h, theta);
          return py::make_tuple(r.error, r.min_step);
        }, py::arg("spec"), py::arg("history"), py::arg("theta"));
  m.def("groove_events", [](const PinGrooveSpec& s, const PinGrooveHistory& h, double theta, double rate) {
          Eigen::VectorXd e(num_events(s));
          pin_groove_events(s, h, theta, rate, e.data());
          return e;
        }, py::arg("spec"), py::arg("history"), py::arg("theta"), py::arg("rate"));
  m.def("groove_update_history",
        [](const PinGrooveSpec& s, PinGrooveHistory& h, double theta, double rate, std::optional<Eigen::VectorXd> margins) {
          if (margins && margins->size() != num_events(s))
            throw std::invalid_argument("margins: expected one per event, " + std::to_string(num_events(s)));
          update_history(s, h, theta, rate, margins ? margins->data() : nullptr);
        }, py::arg("spec"), py::arg("history"), py::arg("theta"), py::arg("rate"), py::arg("margins") = std::nullopt);
  m.def("groove_friction_step_limit",
        static_cast<double (*)(const PinGrooveSpec&, const PinGrooveHistory&, double, double, double)>(
            &friction_step_limit),
        py::arg("spec"), py::arg("history"), py::arg("theta"),
        py::arg("rate"), py::arg("rate_change"));

  m.def("stop_latch_groove", &stop_latch_groove, py::arg("lock"), py::arg("rho"), py::arg("pin_angle") = 0.0);
  m.def("stop_latch_history", &stop_latch_history, py::arg("history"));
  py::class_<PaperGrooveParameters>(m, "PaperGrooveParameters", "joint/lock_profiles.hpp")
      .def(py::init<>())
      .def_readwrite("theta_lock", &PaperGrooveParameters::theta_lock)
      .def_readwrite("pin_angle", &PaperGrooveParameters::pin_angle)
      .def_readwrite("seat", &PaperGrooveParameters::seat)
      .def_readwrite("pin_radius", &PaperGrooveParameters::pin_radius)
      .def_readwrite("notch_depth", &PaperGrooveParameters::notch_depth)
      .def_readwrite("clearance", &PaperGrooveParameters::clearance)
      .def_readwrite("stop_height", &PaperGrooveParameters::stop_height)
      .def_readwrite("track_start", &PaperGrooveParameters::track_start)
      .def_readwrite("preload", &PaperGrooveParameters::preload)
      .def_readwrite("stiffness", &PaperGrooveParameters::stiffness)
      .def_readwrite("stop_below_seat", &PaperGrooveParameters::stop_below_seat)
      .def_readwrite("travel", &PaperGrooveParameters::travel);
  m.def("paper_groove", &paper_groove, py::arg("parameters"), py::arg("law"), py::arg("friction"));

  // Today's lock (joint/hinge_lock.hpp), for comparison.
  m.def("hinge_wall_states", [](const HingeLockSpec& lock, const LockHistory& h, double theta, double rate) {
          WallState stop, latch;
          wall_states(lock, h, theta, rate, &stop, &latch);
          return py::make_tuple(wall_dict(stop), wall_dict(latch));
        }, py::arg("lock"), py::arg("history"), py::arg("theta"), py::arg("rate"));
  m.def("hinge_lock_load", [](const HingeLockSpec& lock, const LockHistory& h, double theta, double rate) {
          const auto l = lock_load(lock, h, theta, rate);
          py::dict d;
          d["torque"] = l.torque;
          d["d_theta"] = l.d_theta;
          d["d_rate"] = l.d_rate;
          d["normal_force"] = l.normal_force;
          return d;
        }, py::arg("lock"), py::arg("history"), py::arg("theta"), py::arg("rate"));
}
