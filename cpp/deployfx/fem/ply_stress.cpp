#include "deployfx/fem/ply_stress.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deployfx/material/transverse_shear.hpp"

namespace deployfx::fem {
namespace {

// The section constants must be the laminate's, to 1e-10 of a scale that suits each block: |A|,
// |D|, sqrt(|A| |D|) for B (a symmetric lay-up's B is round-off), |As|.
void require_same(const char* name, const Eigen::MatrixXd& element, const Eigen::MatrixXd& laminate,
                  double scale) {
  if ((element - laminate).norm() > 1e-10 * scale)
    throw std::invalid_argument(std::string("laminate is not the shell model's section: its ") + name +
                                " differs from the elements'");
}

}  // namespace

PlyRecovery make_ply_recovery(const ShellModel& model, const material::Laminate& laminate,
                              Sampling sampling) {
  const ShellElement& first = model.elements().front();
  const double a = laminate.A().norm(), d = laminate.D().norm();
  require_same("A", first.A(), laminate.A(), a);
  require_same("B", first.B(), laminate.B(), std::sqrt(a * d));
  require_same("D", first.D(), laminate.D(), d);
  require_same("As", first.As(), laminate.As(), laminate.As().norm());

  PlyRecovery r;
  r.sampling = sampling;
  r.num_elements = model.num_elements();
  r.num_dofs = model.num_dofs();
  r.num_plies = static_cast<int>(laminate.plies().size());
  const double g = 1.0 / std::sqrt(3.0);
  const std::vector<std::array<double, 2>> points =
      sampling == Sampling::Centroid
          ? std::vector<std::array<double, 2>>{{0.0, 0.0}}
          : std::vector<std::array<double, 2>>{{-g, -g}, {g, -g}, {g, g}, {-g, g}};
  r.points_per_element = static_cast<int>(points.size());
  const std::size_t n_points = static_cast<std::size_t>(r.num_elements) * points.size();
  r.op.resize(n_points);
  r.points_W.resize(static_cast<Eigen::Index>(n_points), 3);
  r.element_nodes.resize(static_cast<std::size_t>(r.num_elements));
  for (int e = 0; e < r.num_elements; ++e) {
    const ShellElement& el = model.elements()[e];
    for (int a = 0; a < 4; ++a) r.element_nodes[e][a] = model.quads()(e, a);
    const Eigen::Matrix3d Rt = el.R_WE().transpose();
    for (std::size_t p = 0; p < points.size(); ++p) {
      const std::size_t i = e * points.size() + p;
      const ShellElement::StrainOperators s = el.strain_operators(points[p][0], points[p][1]);
      Eigen::Matrix<double, 14, kElementDofs> op_E;
      op_E << s.Bm, s.Bb, el.As() * s.Bs, s.G;
      // d_E = blockdiag(R_WE^T) d_W on the eight 3-blocks of the element's dofs.
      for (int b = 0; b < kElementDofs / 3; ++b) r.op[i].middleCols<3>(3 * b) = op_E.middleCols<3>(3 * b) * Rt;
      r.points_W.row(static_cast<Eigen::Index>(i)) = el.position(points[p][0], points[p][1]).transpose();
    }
  }

  const std::vector<double>& zk = laminate.z();
  std::vector<double> z_stations;
  for (int k = 0; k < r.num_plies; ++k)
    z_stations.insert(z_stations.end(), {zk[k], 0.5 * (zk[k] + zk[k + 1]), zk[k + 1]});
  const std::vector<Eigen::Matrix2d> H = material::equilibrium_shear(laminate, z_stations);
  r.plies.resize(static_cast<std::size_t>(r.num_plies));
  for (int k = 0; k < r.num_plies; ++k) {
    const material::Ply& ply = laminate.plies()[k];
    const double theta = ply.angle_deg * M_PI / 180.0, c = std::cos(theta), s = std::sin(theta);
    Eigen::Matrix2d R;  // (tau_13, tau_23) = R (tau_xz, tau_yz)
    R << c, s, -s, c;
    PlyRecovery::PlyData& d = r.plies[k];
    d.T = material::Orthotropic::strain_rotation(theta);
    d.QT = ply.material.Q() * d.T;
    d.G13 = ply.material.G13();
    d.G23 = ply.material.G23();
    for (int j = 0; j < kPlyStations; ++j) {
      d.z[j] = z_stations[kPlyStations * k + j];
      d.H[j] = R * H[kPlyStations * k + j];
    }
  }
  return r;
}

StrainMeasure strain_measure_from_name(const std::string& value) {
  if (value == "linear") return StrainMeasure::Linear;
  if (value == "green") return StrainMeasure::Green;
  if (value == "von-karman") return StrainMeasure::VonKarman;
  throw std::invalid_argument("strain = '" + value + "' is invalid: must be 'linear', 'green' or 'von-karman'");
}

SectionState section_state(const PlyRecovery& r, const double* u, int e, int p, StrainMeasure measure) {
  Eigen::Matrix<double, kElementDofs, 1> d;
  for (int a = 0; a < 4; ++a)
    d.segment<kNodeDofs>(kNodeDofs * a) = Eigen::Map<const Eigen::Matrix<double, kNodeDofs, 1>>(
        u + static_cast<std::ptrdiff_t>(kNodeDofs) * r.element_nodes[e][a]);
  const auto& op = r.op[static_cast<std::size_t>(e) * r.points_per_element + p];
  SectionState s = op.topRows<8>() * d;
  if (measure == StrainMeasure::Green) {  // Eq. 14: the quadratic part of the Green strain
    const Eigen::Matrix<double, 6, 1> psi = op.bottomRows<6>() * d;
    const Eigen::Vector3d px = psi.head<3>(), py = psi.tail<3>();
    s(0) += 0.5 * px.squaredNorm();
    s(1) += 0.5 * py.squaredNorm();
    s(2) += px.dot(py);
  } else if (measure == StrainMeasure::VonKarman) {  // the normal displacement's gradient alone (E's z)
    const Eigen::Matrix<double, 6, 1> psi = op.bottomRows<6>() * d;
    const double wx = psi(2), wy = psi(5);
    s(0) += 0.5 * wx * wx;
    s(1) += 0.5 * wy * wy;
    s(2) += wx * wy;
  }
  return s;
}

void ply_state(const PlyRecovery& r, const SectionState& s, int k, int j, material::PlyStress* stress,
               material::PlyStress* strain) {
  const PlyRecovery::PlyData& d = r.plies[k];
  const Eigen::Vector3d eps = s.head<3>() + d.z[j] * s.segment<3>(3);  // laminate axes
  const Eigen::Vector2d tau = d.H[j] * s.tail<2>();
  stress->head<3>() = d.QT * eps;
  stress->tail<2>() = tau;
  if (strain) {
    strain->head<3>() = d.T * eps;
    (*strain)(3) = tau(0) / d.G13;
    (*strain)(4) = tau(1) / d.G23;
  }
}

void ply_fields(const PlyRecovery& r, const Eigen::VectorXd& u, StrainMeasure measure, double* stress,
                double* strain) {
  if (u.size() != r.num_dofs)
    throw std::invalid_argument("u has wrong size: expected " + std::to_string(r.num_dofs) +
                                " (6 per node), got " + std::to_string(u.size()));
  if (!u.allFinite()) throw std::invalid_argument("u has non-finite entries");
  std::size_t o = 0;
  material::PlyStress sig, eps;
  for (int e = 0; e < r.num_elements; ++e)
    for (int p = 0; p < r.points_per_element; ++p) {
      const SectionState s = section_state(r, u.data(), e, p, measure);
      for (int k = 0; k < r.num_plies; ++k)
        for (int j = 0; j < kPlyStations; ++j, o += kPlyComponents) {
          ply_state(r, s, k, j, &sig, strain ? &eps : nullptr);
          if (stress) Eigen::Map<material::PlyStress>(stress + o) = sig;
          if (strain) Eigen::Map<material::PlyStress>(strain + o) = eps;
        }
    }
}

}  // namespace deployfx::fem
