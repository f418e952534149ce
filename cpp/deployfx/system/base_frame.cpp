#include "deployfx/system/base_frame.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deployfx/math/check.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::system {

BaseMotion base_motion(bool free, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a) {
  BaseMotion b;
  if (!free) return b;
  b.r_W = q.head<3>();
  b.R_WB = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
  b.v_W = v.head<3>();
  b.w_B = v.segment<3>(3);
  if (a) b.a_W = a->head<3>(), b.wd_B = a->segment<3>(3);
  b.V_B = b.R_WB.transpose() * b.v_W;
  b.a_B = b.R_WB.transpose() * b.a_W;
  return b;
}

Eigen::VectorXd retract_with_base(bool free, const Eigen::VectorXd& q, const Eigen::VectorXd& dq) {
  Eigen::VectorXd out = q;
  if (!free) return out += dq;
  out.head<3>() += dq.head<3>();
  const Eigen::Quaterniond Q(q(3), q(4), q(5), q(6));
  const Eigen::Quaterniond Q1 = (Q * quaternion_exp(dq.segment<3>(3))).normalized();  // R_WB exp(dpsi)
  out.segment<4>(3) << Q1.w(), Q1.x(), Q1.y(), Q1.z();
  const Eigen::Index rest = q.size() - kBasePositions;
  out.tail(rest) += dq.tail(rest);
  return out;
}

void check_rigid_inertia(const std::string& name, const body::RigidInertia& body, bool definite) {
  if (definite) {
    require_positive(name + ".mass", body.mass, "(kg)");
  } else if (!(std::isfinite(body.mass) && body.mass >= 0)) {
    throw_out_of_range(name + ".mass", body.mass, "finite and >= 0 (kg)");
  }
  if (!body.com.allFinite()) throw std::invalid_argument(name + ".com must be finite (m)");
  const Eigen::Matrix3d& J = body.inertia_com;
  const bool symmetric = J.allFinite() && (J - J.transpose()).norm() <= 1e-12 * std::max(1.0, J.norm());
  const double low = symmetric ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J).eigenvalues().minCoeff() : -1.0;
  if (!symmetric || !(definite ? low > 0 : low >= -1e-12 * J.norm()))
    throw std::invalid_argument(name + ".inertia must be symmetric positive " +
                                (definite ? "definite" : "semidefinite") + " (kg m^2)");
}

}  // namespace deployfx::system
