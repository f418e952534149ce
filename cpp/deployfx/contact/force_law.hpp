#pragma once
// Normal force laws of a compliant contact (the hinge lock's latch on its seat), as functions of
// the penetration delta (m, > 0 in contact) and its rate delta_dot (m/s, > 0 approaching):
//   Kelvin-Voigt-Hertz (You et al. 2016):        F = K delta^n + D delta_dot
//   Hunt & Crossley, J. Appl. Mech. 42 (1975) 440:  F = K delta^n (1 + c delta_dot / v0),
//     with the hysteresis factor c = 3 (1 - e) / 2                          (Hunt-Crossley)
//                                c = 3 (1 - e^2) / 4   (Lankarani & Nikravesh, J. Mech. Des.
//                                                       112 (1990) 369)
//                                c = 8 (1 - e) / (5 e) (Flores, Machado, Silva & Martins,
//                                                       Multibody Syst. Dyn. 25 (2011) 357)
// K in N/m^n, n >= 1 (Hertz: 3/2), D in N s/m, e the restitution coefficient the law is tuned
// for, v0 > 0 the approach speed at contact onset (the caller keeps it per contact). The law
// never pulls: F = max(F, 0), and F = 0 for delta <= 0.
// The restitution these laws really give in a 1-DOF impact solves the exact relation
//   x - ln(1 + x) = -e_eff x - ln(1 - e_eff x),  x = c
// (Carvalho & Martins, Mech. Mach. Theory, 2019; derived in docs/research/engine-references.md
// Sec. 4): Hunt-Crossley and Lankarani-Nikravesh are accurate only for e near 1 (they never give
// e_eff below ~0.49 and ~0.66), Flores stays within 0.045 of e for all e. Kelvin-Voigt's
// restitution depends on v0, and its force jumps to D v0 at onset.
namespace deployfx::contact {

/// F (N) and its partial derivatives (N/m, N s/m); the derivatives are 0 where the clamp is active.
struct ContactForce {
  double F = 0, dF_ddelta = 0, dF_ddelta_dot = 0;
};

class ContactLaw {
 public:
  enum class Kind { kKelvinVoigtHertz, kHuntCrossley, kLankaraniNikravesh, kFlores };

  /// Throws std::invalid_argument naming the parameter: K > 0, n >= 1 (keeps dF/ddelta bounded
  /// as delta -> 0); Kelvin-Voigt: D >= 0 and e left at 1 (unused); the Hunt-Crossley family:
  /// 0 < e <= 1 and D left at 0 (its damping follows from e).
  ContactLaw(Kind kind, double K, double n = 1.5, double D = 0.0, double e = 1.0);

  Kind kind() const { return kind_; }
  double K() const { return K_; }
  double n() const { return n_; }
  double D() const { return D_; }
  double e() const { return e_; }
  /// c in F = K delta^n (1 + c delta_dot / v0); 0 for Kelvin-Voigt.
  double hysteresis_factor() const { return c_; }
  /// Whether evaluate() reads v0 (the Hunt-Crossley family).
  bool needs_onset_speed() const { return kind_ != Kind::kKelvinVoigtHertz; }

  /// F(delta, delta_dot) and its partials. v0 (m/s) is read only in contact by the Hunt-Crossley
  /// family, which then requires v0 > 0 (std::invalid_argument otherwise). Infinite inputs count
  /// as +-DBL_MAX and every intermediate saturates there, so finite in gives finite out; NaN
  /// delta or delta_dot gives NaN out.
  ContactForce evaluate(double delta, double delta_dot, double v0) const;

 private:
  Kind kind_;
  double K_, n_, D_, e_, c_;
};

/// "kelvin-voigt-hertz", "hunt-crossley", "lankarani-nikravesh", "flores".
const char* to_string(ContactLaw::Kind kind);

}  // namespace deployfx::contact
