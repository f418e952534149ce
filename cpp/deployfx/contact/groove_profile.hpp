#pragma once
// A planar groove profile in a body's frame: a chain of line segments and circular arcs in the
// hinge plane (2-D, m), and the closest-point queries a pin (a circle of radius rho about a centre
// c) needs for compliant contact (You et al. 2016, Eq. 45: F_n along n, friction along t).
//
// Side convention: walking the chain from its first element to its last, the free space (where
// the pin lives) is on the LEFT and the material on the right. The outward normal n (material
// to free space) is the left normal of the travel direction t: n = (-t_y, t_x), t = (n_y, -n_x).
// So an arc that turns left (radius > 0, counter-clockwise) is concave seen from the pin (a seat),
// one that turns right (radius < 0, clockwise) is convex (a bump); a vertex where the chain turns
// right is a convex corner, one where it turns left a concave corner.
//
// Facets. The chain is split at its concave corners into facets, each one contact: within a facet
// (elements joined smoothly or at convex corners) the distance from a point on the free side is
// continuously differentiable, and at a convex corner the normal turns with the pin over the
// corner's fan of directions (the closest point is then the vertex, n = (c - v)/|c - v|). A pin
// wedged in a concave corner touches the two facets that meet there: two contacts, each smooth.
// A facet's query is "in range" when the closest point is not one of its ends (a free end of the
// chain, or a concave corner); out of range, the facet does not touch the pin.
//
// Queries for a pin at c (m) of radius rho (m) against one facet:
//   gap   = (c - p)·n - rho (m), p the closest point: > 0 clear, < 0 penetration (-gap = delta),
//   d gap / d c = n, d n / d c = H = kappa t t^T (the Hessian of the signed distance), with
//   kappa = 0 on a segment, -s/|c - m| on an arc of centre m turning with sign s (+1 left),
//   +-1/|c - v| at a convex vertex v (the sign of the side), so that a Newton matrix can be
//   analytic: d^2 gap / dc^2 = H.
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace deployfx::contact {

/// One element of a chain: a segment or a circular arc from `start` to `end` (m).
class GrooveElement {
 public:
  enum class Kind { kLine, kArc };

  /// A segment; throws std::invalid_argument unless start and end are finite and distinct.
  static GrooveElement line(const Eigen::Vector2d& start, const Eigen::Vector2d& end);
  /// The minor arc (sweep <= pi) of signed radius `radius` (m): > 0 turns left (counter-clockwise,
  /// centre on the left of the chord), < 0 turns right; |radius| >= half the chord.
  static GrooveElement arc(const Eigen::Vector2d& start, const Eigen::Vector2d& end, double radius);
  /// The arc about `centre` from start to end, counter-clockwise if `ccw` (any sweep in (0, 2 pi));
  /// start and end must be equidistant from the centre (to 1e-9 relative).
  static GrooveElement arc_about(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                 const Eigen::Vector2d& centre, bool ccw);

  Kind kind() const { return kind_; }
  const Eigen::Vector2d& start() const { return a_; }
  const Eigen::Vector2d& end() const { return b_; }
  const Eigen::Vector2d& centre() const { return m_; }  ///< arcs only
  double radius() const { return R_; }                   ///< arcs: > 0 (the magnitude)
  double sweep() const { return sweep_; }                ///< arcs: signed, rad (> 0 ccw)
  double length() const { return length_; }              ///< m
  /// Unit travel direction at arc length u in [0, length] from the start.
  Eigen::Vector2d tangent(double u) const;
  Eigen::Vector2d point(double u) const;
  /// point(u) and tangent(u) together, the same values (an arc's angle and its sine and cosine
  /// once: GrooveProfile::query asks for both at every contact evaluation).
  std::pair<Eigen::Vector2d, Eigen::Vector2d> frame(double u) const;
  /// The point of the element nearest to c, as its arc length u in [0, length]; `interior` is
  /// false when the nearest point of the element's line or circle lies outside the element (u is
  /// then clamped to the nearer end).
  double project(const Eigen::Vector2d& c, bool* interior) const;

 private:
  Kind kind_ = Kind::kLine;
  Eigen::Vector2d a_, b_, m_ = Eigen::Vector2d::Zero();
  double R_ = 0, phi0_ = 0, sweep_ = 0, length_ = 0;
};

/// The answer of a query for a pin against one facet (see the header comment).
struct PinQuery {
  bool in_range = false;  ///< the closest point is not an end of the facet
  double gap = 0;         ///< m, (c - p)·n - rho
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< p, the closest point of the facet (m)
  Eigen::Vector2d n = Eigen::Vector2d::Zero();      ///< outward unit normal at p (= d gap / d c)
  Eigen::Vector2d t = Eigen::Vector2d::Zero();      ///< unit tangent, the chain's direction
  Eigen::Matrix2d dn_dc = Eigen::Matrix2d::Zero();  ///< d n / d c (1/m), = d^2 gap / d c^2
  int facet = -1;
  int element = -1;       ///< the element of p (for a vertex, the one it ends)
  bool at_vertex = false; ///< p is a convex vertex of the facet
  double chain_length = 0;  ///< m, arc length of p along the chain from its start
};

/// The distance (m) between a segment [p0, p1] and a facet, and the parameter in [0, 1] of the
/// segment's point that attains it (0 where the segment crosses the facet).
struct SegmentDistance {
  double distance = 0, param = 0;
};

class GrooveProfile {
 public:
  /// Throws std::invalid_argument naming the element when the chain is empty or not continuous
  /// (each element's start within 1e-9 m x max(1, extent) of the previous end). A chain whose
  /// last end meets its first start is closed.
  explicit GrooveProfile(std::vector<GrooveElement> elements);

  int num_elements() const { return static_cast<int>(elements_.size()); }
  /// An identity of this profile's geometry: distinct for every profile constructed in the
  /// process, shared by its copies (a memo of a query keys on it: joint::FollowerMemo).
  std::uint64_t id() const { return id_; }
  const GrooveElement& element(int k) const { return elements_[static_cast<std::size_t>(k)]; }
  bool closed() const { return closed_; }
  int num_facets() const { return static_cast<int>(facets_.size()); }
  /// Facet f's elements: first, count (indices wrap on a closed chain).
  int facet_first(int f) const { return facets_[static_cast<std::size_t>(f)].first; }
  int facet_count(int f) const { return facets_[static_cast<std::size_t>(f)].count; }
  int facet_of_element(int k) const { return facet_of_[static_cast<std::size_t>(k)]; }
  /// The turn at the vertex ending element k (rad, > 0 left = concave, < 0 right = convex);
  /// 0 at a free end.
  double turn(int k) const { return turn_[static_cast<std::size_t>(k)]; }

  /// Pin at c (m) of radius rho (m, >= 0) against facet f.
  PinQuery query(int f, const Eigen::Vector2d& c, double rho) const;
  /// Against the whole profile: the in-range facet nearest to c (unsigned distance); in_range is
  /// false (and gap +inf) when no facet is in range.
  PinQuery closest(const Eigen::Vector2d& c, double rho) const;
  /// The distance between the segment [p0, p1] and facet f (its elements, ends included).
  SegmentDistance segment_distance(int f, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) const;

 private:
  struct Facet {
    int first = 0, count = 0;
    bool loop = false;  ///< a closed chain without concave corners: no ends
  };
  const GrooveElement& elem(int k) const;  // k taken modulo the element count
  std::vector<GrooveElement> elements_;
  std::vector<double> offset_;  // arc length at each element's start
  std::vector<double> turn_;
  std::vector<Facet> facets_;
  std::vector<int> facet_of_;
  bool closed_ = false;
  std::uint64_t id_ = 0;
};

}  // namespace deployfx::contact
