#include "deployfx/joint/lock_profiles.hpp"

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "deployfx/math/check.hpp"

namespace deployfx::joint {
namespace {

using contact::GrooveElement;
using Eigen::Vector2d;

Vector2d e_r(double psi) { return {std::cos(psi), std::sin(psi)}; }
Vector2d e_psi(double psi) { return {-std::sin(psi), std::cos(psi)}; }

}  // namespace

PinGrooveSpec stop_latch_groove(const HingeLockSpec& lock, double rho, double pin_angle) {
  lock.validate();
  const double r = lock.pin_radius;
  if (!(std::isfinite(rho) && rho >= 0 && rho < 0.5 * r)) {
    std::ostringstream s;
    s << "in [0, lock.pin_radius / 2 = " << 0.5 * r << ") (m)";
    throw_out_of_range("rho", rho, s.str());
  }
  require_finite("pin_angle", pin_angle, "(rad)");
  const double psi_stop = lock.theta_lock + pin_angle, psi_latch = lock.theta_latch() + pin_angle;
  const double h = rho + 0.25 * r;  // the walls' reach on either side of the pin's path
  // Free space on the left: down the stop wall, across the bottom, up the latch wall.
  const Vector2d P_s = r * e_r(psi_stop) + rho * e_psi(psi_stop);
  const Vector2d P_l = r * e_r(psi_latch) - rho * e_psi(psi_latch);
  const Vector2d S_out = P_s + h * e_r(psi_stop), S_in = P_s - h * e_r(psi_stop);
  const Vector2d L_in = P_l - h * e_r(psi_latch), L_out = P_l + h * e_r(psi_latch);
  contact::GrooveProfile profile({GrooveElement::line(S_out, S_in), GrooveElement::line(S_in, L_in),
                                  GrooveElement::line(L_in, L_out)});
  return PinGrooveSpec(std::move(profile), r, pin_angle, rho, lock.law, lock.friction);
}

PinGrooveHistory stop_latch_history(const LockHistory& h) {
  PinGrooveHistory g;
  g.facets.resize(3);
  g.facets[kStopFacet] = {true,     h.stop_contact, h.stop_inside, h.stop_v0,
                          h.stop_T, h.stop_resolution, h.stop_track};
  g.facets[kLatchFacet] = {h.latched, h.latch_contact, h.latch_inside, h.latch_v0,
                           h.latch_T, h.latch_resolution, h.latch_track};
  return g;
}

PinGrooveSpec paper_groove(const PaperGrooveParameters& p, const contact::ContactLaw& law,
                           const contact::CoulombFriction& friction) {
  require_finite("paper_groove.theta_lock", p.theta_lock, "(rad)");
  require_finite("paper_groove.pin_angle", p.pin_angle, "(rad)");
  require_positive("paper_groove.seat", p.seat, "(m)");
  require_positive("paper_groove.pin_radius", p.pin_radius, "(m)");
  const double rho = p.pin_radius;
  if (!(p.seat > 2 * rho)) throw_out_of_range("paper_groove.seat", p.seat, "> 2 pin_radius (m)");
  // The seated pin must meet the flanks at its centre's height: deeper than the pin's radius.
  if (!(std::isfinite(p.notch_depth) && p.notch_depth > rho))
    throw_out_of_range("paper_groove.notch_depth", p.notch_depth, "> pin_radius (m)");
  if (!(std::isfinite(p.clearance) && p.clearance >= 0 && p.clearance < 0.5 * p.seat))
    throw_out_of_range("paper_groove.clearance", p.clearance, "in [0, seat / 2) (m)");
  require_positive("paper_groove.stop_height", p.stop_height, "(m)");
  const double psi_stop = p.theta_lock + p.pin_angle, psi_latch = psi_stop - p.clearance / p.seat;
  const double R_n = p.seat - rho, R_c = R_n + p.notch_depth, R_top = R_c + p.stop_height;
  // The flanks: lines parallel to the radius through the seated pin's centre at its stop and latch
  // angles, offset by rho, from the notch bottom (radius R_n) up to R_top (stop) and R_c (latch).
  auto flank = [&](double psi, double side, double R) {
    return Vector2d(p.seat * e_r(psi) + side * rho * e_psi(psi) + (std::sqrt(R * R - rho * rho) - p.seat) * e_r(psi));
  };
  const Vector2d S_out = flank(psi_stop, 1, R_top), S_in = flank(psi_stop, 1, R_n);
  const Vector2d A_in = flank(psi_latch, -1, R_n), V = flank(psi_latch, -1, R_c);
  const double psi_track = p.track_start + p.pin_angle;
  const double psi_V = std::atan2(V.y(), V.x());
  if (!(std::isfinite(p.track_start) && psi_track < psi_V && psi_track > psi_V - 6.0))
    throw_out_of_range("paper_groove.track_start", p.track_start, "below the latch angle, within 6 rad of it (rad)");
  const Vector2d O = Vector2d::Zero(), T_end = R_c * e_r(psi_track);
  contact::GrooveProfile profile({GrooveElement::line(S_out, S_in), GrooveElement::arc_about(S_in, A_in, O, false),
                                  GrooveElement::line(A_in, V), GrooveElement::arc_about(V, T_end, O, false)});
  LatchSpring latch{true, p.seat - p.stop_below_seat, p.travel, p.preload, p.stiffness};
  if (!(p.stop_below_seat > 0 && p.stop_below_seat < R_n))
    throw_out_of_range("paper_groove.stop_below_seat", p.stop_below_seat, "in (0, seat - pin_radius) (m)");
  const double ride = R_c + rho;  // the pin's centre on the track
  if (!(p.travel > ride - latch.stop)) {
    std::ostringstream s;
    s << "> the ride height above the bore stop, " << ride - latch.stop << " (m)";
    throw_out_of_range("paper_groove.travel", p.travel, s.str());
  }
  return PinGrooveSpec(std::move(profile), p.seat, p.pin_angle, rho, law, friction, latch);
}

}  // namespace deployfx::joint
