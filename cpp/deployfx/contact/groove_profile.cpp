#include "deployfx/contact/groove_profile.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::contact {
namespace {

using Eigen::Matrix2d;
using Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
std::atomic<std::uint64_t> next_profile_id{1};
// A vertex turning by less than this (rad) is smooth: it does not split a facet.
constexpr double kSmoothTurn = 1e-9;

std::string str(const Vector2d& p) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

bool finite(const Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
double cross(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
Vector2d left(const Vector2d& t) { return {-t.y(), t.x()}; }   // n from t
Vector2d right(const Vector2d& n) { return {n.y(), -n.x()}; }  // t from n
double wrap(double a) { return a - 2 * kPi * std::floor(a / (2 * kPi)); }  // into [0, 2 pi)

void require_points(const char* what, const Vector2d& a, const Vector2d& b) {
  if (!finite(a) || !finite(b) || a == b)
    throw std::invalid_argument(std::string(what) + ": start = " + str(a) + " and end = " + str(b) +
                                " must be finite and distinct (m)");
}

// Distance from c to the segment [a, b] and the parameter in [0, 1] of its nearest point.
SegmentDistance point_segment(const Vector2d& c, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double L2 = ab.squaredNorm();
  const double s = L2 > 0 ? std::clamp((c - a).dot(ab) / L2, 0.0, 1.0) : 0.0;
  return {(a + s * ab - c).norm(), s};
}

void keep(SegmentDistance& best, double d, double param) {
  if (d < best.distance) best = {d, param};
}

// Segment [p0, p1] against the segment [a, b].
void segment_line(const Vector2d& p0, const Vector2d& p1, const Vector2d& a, const Vector2d& b, SegmentDistance& best) {
  const Vector2d r = p1 - p0, q = b - a;
  const double den = cross(r, q);
  if (den != 0) {  // crossing: zero distance at the intersection
    const double s = cross(a - p0, q) / den, u = cross(a - p0, r) / den;
    if (s >= 0 && s <= 1 && u >= 0 && u <= 1) return keep(best, 0.0, s);
  }
  keep(best, point_segment(p0, a, b).distance, 0.0);
  keep(best, point_segment(p1, a, b).distance, 1.0);
  const auto da = point_segment(a, p0, p1), db = point_segment(b, p0, p1);
  keep(best, da.distance, da.param);
  keep(best, db.distance, db.param);
}

// Segment [p0, p1] against an arc: endpoints against the other, the segment's point nearest the
// centre, and the crossings of the segment with the arc.
void segment_arc(const Vector2d& p0, const Vector2d& p1, const GrooveElement& e, SegmentDistance& best) {
  const auto da = point_segment(e.start(), p0, p1), db = point_segment(e.end(), p0, p1);
  keep(best, da.distance, da.param);
  keep(best, db.distance, db.param);
  for (double s : {0.0, 1.0}) {
    const Vector2d p = s == 0 ? p0 : p1;
    bool in = false;
    keep(best, (e.point(e.project(p, &in)) - p).norm(), s);
  }
  const Vector2d m = e.centre(), r = p1 - p0;
  const auto dm = point_segment(m, p0, p1);
  const Vector2d q = p0 + dm.param * r;
  bool in = false;
  if (dm.distance >= e.radius() && dm.distance > 0) {
    e.project(q, &in);
    if (in) keep(best, dm.distance - e.radius(), dm.param);
  }
  // |p0 + s r - m| = R: a s^2 + 2 b s + c = 0.
  const double A = r.squaredNorm(), B = r.dot(p0 - m), C = (p0 - m).squaredNorm() - e.radius() * e.radius();
  const double disc = B * B - A * C;
  if (A > 0 && disc >= 0) {
    for (double sgn : {-1.0, 1.0}) {
      const double s = (-B + sgn * std::sqrt(disc)) / A;
      if (s < 0 || s > 1) continue;
      e.project(p0 + s * r, &in);
      if (in) keep(best, 0.0, s);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------- elements

GrooveElement GrooveElement::line(const Vector2d& start, const Vector2d& end) {
  require_points("line", start, end);
  GrooveElement e;
  e.kind_ = Kind::kLine;
  e.a_ = start;
  e.b_ = end;
  e.length_ = (end - start).norm();
  return e;
}

GrooveElement GrooveElement::arc(const Vector2d& start, const Vector2d& end, double radius) {
  require_points("arc", start, end);
  const double chord = (end - start).norm();
  if (!(std::isfinite(radius) && std::abs(radius) >= 0.5 * chord * (1 - 1e-12))) {
    std::ostringstream s;
    s << "|radius| >= half the chord, " << 0.5 * chord << " (m; > 0 turns left, < 0 right)";
    throw_out_of_range("arc.radius", radius, s.str());
  }
  const double R = std::abs(radius), sgn = radius > 0 ? 1.0 : -1.0;
  const Vector2d u = (end - start) / chord;
  const double h = std::sqrt(std::max(R * R - 0.25 * chord * chord, 0.0));
  GrooveElement e;
  e.kind_ = Kind::kArc;
  e.a_ = start;
  e.b_ = end;
  e.m_ = 0.5 * (start + end) + sgn * h * left(u);  // the minor arc's centre: on its turning side
  e.R_ = R;
  e.phi0_ = std::atan2(start.y() - e.m_.y(), start.x() - e.m_.x());
  e.sweep_ = sgn * 2 * std::asin(std::min(1.0, 0.5 * chord / R));
  e.length_ = R * std::abs(e.sweep_);
  return e;
}

GrooveElement GrooveElement::arc_about(const Vector2d& start, const Vector2d& end, const Vector2d& centre, bool ccw) {
  require_points("arc_about", start, end);
  if (!finite(centre)) throw std::invalid_argument("arc_about: centre = " + str(centre) + " must be finite (m)");
  const double Ra = (start - centre).norm(), Rb = (end - centre).norm();
  if (!(Ra > 0 && std::abs(Ra - Rb) <= 1e-9 * std::max(Ra, Rb))) {
    std::ostringstream s;
    s << "at the same distance from centre = " << str(centre) << " as the start, " << Ra << " (to 1e-9 relative; m)";
    throw_out_of_range("arc_about: |end - centre|", Rb, s.str());
  }
  GrooveElement e;
  e.kind_ = Kind::kArc;
  e.a_ = start;
  e.b_ = end;
  e.m_ = centre;
  e.R_ = Ra;
  e.phi0_ = std::atan2(start.y() - centre.y(), start.x() - centre.x());
  const double phi1 = std::atan2(end.y() - centre.y(), end.x() - centre.x());
  e.sweep_ = ccw ? wrap(phi1 - e.phi0_) : -wrap(e.phi0_ - phi1);
  e.length_ = Ra * std::abs(e.sweep_);
  return e;
}

Vector2d GrooveElement::tangent(double u) const {
  if (kind_ == Kind::kLine) return (b_ - a_) / length_;
  const double s = sweep_ > 0 ? 1.0 : -1.0, phi = phi0_ + s * u / R_;
  return s * Vector2d(-std::sin(phi), std::cos(phi));
}

Vector2d GrooveElement::point(double u) const {
  if (kind_ == Kind::kLine) return a_ + u * (b_ - a_) / length_;
  const double phi = phi0_ + (sweep_ > 0 ? 1.0 : -1.0) * u / R_;
  return m_ + R_ * Vector2d(std::cos(phi), std::sin(phi));
}

std::pair<Vector2d, Vector2d> GrooveElement::frame(double u) const {
  if (kind_ == Kind::kLine) return {point(u), tangent(u)};
  const double s = sweep_ > 0 ? 1.0 : -1.0, phi = phi0_ + s * u / R_;
  const double c = std::cos(phi), sn = std::sin(phi);
  return {m_ + R_ * Vector2d(c, sn), s * Vector2d(-sn, c)};
}

double GrooveElement::project(const Vector2d& c, bool* interior) const {
  if (kind_ == Kind::kLine) {
    const double u = (c - a_).dot(b_ - a_) / length_;
    *interior = u >= 0 && u <= length_;
    return std::clamp(u, 0.0, length_);
  }
  const Vector2d d = c - m_;
  if (d.x() == 0 && d.y() == 0) {  // at the centre every point is nearest: take the middle
    *interior = true;
    return 0.5 * length_;
  }
  const double phi = std::atan2(d.y(), d.x());
  const double alpha = sweep_ > 0 ? wrap(phi - phi0_) : wrap(phi0_ - phi);
  *interior = alpha <= std::abs(sweep_);
  if (*interior) return R_ * alpha;
  return (c - a_).squaredNorm() <= (c - b_).squaredNorm() ? 0.0 : length_;
}

// ---------------------------------------------------------------- the chain

GrooveProfile::GrooveProfile(std::vector<GrooveElement> elements)
    : elements_(std::move(elements)), id_(next_profile_id.fetch_add(1, std::memory_order_relaxed)) {
  const int n = num_elements();
  if (n == 0) throw std::invalid_argument("profile.elements is empty: a profile needs at least one element");
  double extent = 0;
  for (const auto& e : elements_) extent = std::max({extent, e.start().cwiseAbs().maxCoeff(), e.end().cwiseAbs().maxCoeff()});
  const double tol = 1e-9 * std::max(1.0, extent);
  for (int k = 1; k < n; ++k) {
    const Vector2d prev = element(k - 1).end(), start = element(k).start();
    if ((start - prev).norm() > tol) {
      std::ostringstream s;
      s.precision(10);
      s << "profile.elements[" << k << "].start = " << str(start) << " is out of range: must be within " << tol
        << " m of elements[" << k - 1 << "].end = " << str(prev) << " (the chain must be continuous)";
      throw std::invalid_argument(s.str());
    }
  }
  closed_ = n >= 2 && (element(0).start() - element(n - 1).end()).norm() <= tol;
  offset_.resize(static_cast<std::size_t>(n));
  turn_.assign(static_cast<std::size_t>(n), 0.0);
  double s = 0;
  for (int k = 0; k < n; ++k) {
    offset_[static_cast<std::size_t>(k)] = s;
    s += element(k).length();
    if (k + 1 < n || closed_) {
      const Vector2d t_out = element(k).tangent(element(k).length()), t_in = elem(k + 1).tangent(0.0);
      turn_[static_cast<std::size_t>(k)] = std::atan2(cross(t_out, t_in), t_out.dot(t_in));
    }
  }
  auto concave = [&](int k) { return turn_[static_cast<std::size_t>(k)] > kSmoothTurn; };
  // Facets: split after every concave vertex; a closed chain starts after its first one.
  int first = 0;
  if (closed_) {
    first = -1;
    for (int k = 0; k < n && first < 0; ++k)
      if (concave(k)) first = (k + 1) % n;
    if (first < 0) facets_.push_back({0, n, true});
  }
  if (facets_.empty()) {
    int start = first, count = 0;
    for (int i = 0; i < n; ++i) {
      const int k = (first + i) % n;
      ++count;
      if (concave(k) || i == n - 1) {
        facets_.push_back({start, count, false});
        start = (k + 1) % n;
        count = 0;
      }
    }
  }
  facet_of_.assign(static_cast<std::size_t>(n), 0);
  for (int f = 0; f < num_facets(); ++f)
    for (int i = 0; i < facet_count(f); ++i) facet_of_[static_cast<std::size_t>((facet_first(f) + i) % n)] = f;
}

const GrooveElement& GrooveProfile::elem(int k) const {
  const int n = num_elements();
  return elements_[static_cast<std::size_t>(((k % n) + n) % n)];
}

PinQuery GrooveProfile::query(int f, const Vector2d& c, double rho) const {
  if (f < 0 || f >= num_facets())
    throw std::invalid_argument("facet = " + std::to_string(f) + " is out of range: must be in [0, " +
                                std::to_string(num_facets() - 1) + "]");
  const Facet& F = facets_[static_cast<std::size_t>(f)];
  PinQuery q;
  q.facet = f;
  double best = kInf, u_best = 0;
  std::pair<Vector2d, Vector2d> frame_best;  // point and tangent at u_best
  for (int i = 0; i < F.count; ++i) {
    const int k = (F.first + i) % num_elements();
    const GrooveElement& e = elem(k);
    bool interior = false;
    const double u = e.project(c, &interior);
    if (interior) {
      const std::pair<Vector2d, Vector2d> pt = e.frame(u);
      const double d = (c - pt.first).norm();
      if (d < best) {
        best = d;
        q.element = k;
        q.at_vertex = false;
        u_best = u;
        frame_best = pt;
      }
    }
    if (i + 1 < F.count || F.loop) {  // the facet's inner vertex at the end of element k
      const double d = (c - e.end()).norm();
      if (d < best) {
        best = d;
        q.element = k;
        q.at_vertex = true;
      }
    }
  }
  double d_ends = kInf;
  if (!F.loop) {
    d_ends = std::min((c - elem(F.first).start()).norm(), (c - elem(F.first + F.count - 1).end()).norm());
  }
  q.in_range = best <= d_ends && std::isfinite(best);
  if (q.element < 0) {  // only the ends are near: report the nearer end, out of range
    q.gap = kInf;
    return q;
  }
  const GrooveElement& e = elem(q.element);
  const double kappa_sign = e.kind() == GrooveElement::Kind::kArc ? (e.sweep() > 0 ? -1.0 : 1.0) : 0.0;
  if (!q.at_vertex) {
    q.point = frame_best.first;
    q.n = left(frame_best.second);
    q.gap = (c - q.point).dot(q.n) - rho;
    q.chain_length = offset_[static_cast<std::size_t>(q.element)] + u_best;
    if (e.kind() == GrooveElement::Kind::kArc) {
      const double r = (c - e.centre()).norm();
      if (r > 0) q.dn_dc = kappa_sign / r * right(q.n) * right(q.n).transpose();  // H = kappa t t^T
    }
  } else {
    q.point = e.end();
    q.chain_length = offset_[static_cast<std::size_t>(q.element)] + e.length();
    const Vector2d b = left(e.tangent(e.length())) + left(elem(q.element + 1).tangent(0.0));  // the fan's bisector
    const Vector2d d = c - q.point;
    const double r = d.norm();
    if (r > 0) {
      const double side = d.dot(b) >= 0 ? 1.0 : -1.0;
      q.n = side * d / r;
      q.gap = side * r - rho;
      q.dn_dc = side / r * right(q.n) * right(q.n).transpose();
    } else {  // the centre on the vertex: n along the bisector, curvature undefined (left 0)
      q.n = b.norm() > 0 ? Vector2d(b.normalized()) : left(e.tangent(e.length()));
      q.gap = -rho;
    }
  }
  q.t = right(q.n);
  return q;
}

PinQuery GrooveProfile::closest(const Vector2d& c, double rho) const {
  PinQuery best;
  best.gap = kInf;
  double d_best = kInf;
  for (int f = 0; f < num_facets(); ++f) {
    const PinQuery q = query(f, c, rho);
    if (!q.in_range) continue;
    const double d = std::abs(q.gap + rho);
    if (d < d_best) {
      d_best = d;
      best = q;
    }
  }
  return best;
}

SegmentDistance GrooveProfile::segment_distance(int f, const Vector2d& p0, const Vector2d& p1) const {
  if (f < 0 || f >= num_facets())
    throw std::invalid_argument("facet = " + std::to_string(f) + " is out of range: must be in [0, " +
                                std::to_string(num_facets() - 1) + "]");
  SegmentDistance best{kInf, 0.0};
  const Facet& F = facets_[static_cast<std::size_t>(f)];
  for (int i = 0; i < F.count; ++i) {
    const GrooveElement& e = elem(F.first + i);
    if (e.kind() == GrooveElement::Kind::kLine)
      segment_line(p0, p1, e.start(), e.end(), best);
    else
      segment_arc(p0, p1, e, best);
  }
  return best;
}

}  // namespace deployfx::contact
