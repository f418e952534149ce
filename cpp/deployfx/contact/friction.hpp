#pragma once
// Coulomb friction regularised at low slip speed, for the hinge lock's sliding latch:
//   F_t = -mu F_n s(v_t),  s(v) = tanh(v / v_reg),
//   dF_t/dv_t = -mu F_n (1 - s^2) / v_reg,  dF_t/dF_n = -mu s,
// with v_t the slip velocity (m/s), F_n >= 0 the normal force (N; F_n < 0, no contact, gives no
// friction) and v_reg > 0 (m/s) the slip speed below which the law turns viscous, with slope
// mu F_n / v_reg at v_t = 0. The tanh keeps F_t smooth for Newton iterations; |F_t| reaches
// mu F_n to within 4.2e-9 relative at |v_t| = 10 v_reg, and F_t v_t <= 0 always (dissipative).
// The price: no true sticking; under a tangential load F < mu F_n the contact creeps at
// v_reg atanh(F / (mu F_n)) (Pennestri et al., Nonlinear Dyn. 83 (2016) 1785, review of
// regularised friction models).
namespace deployfx::contact {

/// F_t (N) and its partial derivatives (N s/m, dimensionless).
struct FrictionForce {
  double F_t = 0, dF_dv_t = 0, dF_dF_n = 0;
};

class CoulombFriction {
 public:
  /// Throws std::invalid_argument naming the parameter: mu >= 0, v_reg > 0 (m/s).
  explicit CoulombFriction(double mu, double v_reg = 1e-4);

  double mu() const { return mu_; }
  double v_reg() const { return v_reg_; }

  /// Infinite inputs count as +-DBL_MAX and results saturate there (finite in, finite out);
  /// NaN in gives NaN out.
  FrictionForce evaluate(double v_t, double F_n) const;

 private:
  double mu_, v_reg_;
};

}  // namespace deployfx::contact
