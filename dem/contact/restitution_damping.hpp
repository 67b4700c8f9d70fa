#pragma once
// The damping of a Hertz contact, F_d = -2 sqrt(5/6) beta sqrt(S_n m*) v_n with
// S_n = 2 E* sqrt(R* delta), makes the restitution independent of the impact
// speed and of the material: in units where the elastic force is X^{3/2} the
// collision obeys X'' = -X^{3/2} - sqrt(5) beta X^{1/4} X' (the total force kept
// repulsive). So e is one function of beta, computed here by integrating that
// equation, and inverted by bisection.

namespace demcal::dem {

// The restitution a Hertzian collision with damping parameter beta >= 0 yields.
double restitution_for_damping_beta(double beta);

// The largest damping parameter the integration above resolves: beyond it
// the collision is stiffer than its step (about beta = 5e4 the computed e
// grows again), so a root search there never ends.
inline constexpr double kMaxResolvedDampingBeta = 1000.0;

// The smallest restitution the exact model reaches: e(kMaxResolvedDampingBeta), ~2.4e-7.
double smallest_resolved_restitution();

// The damping parameter beta that yields restitution e in [smallest_resolved_restitution(), 1];
// a smaller e (but > 0) throws std::invalid_argument naming that bound.
double damping_beta_for_restitution(double restitution);

// The linear-spring formula beta = -ln e / sqrt(ln^2 e + pi^2).
double linear_spring_damping_beta(double restitution);

}  // namespace demcal::dem
