#include "simulate/contact_block.hpp"

namespace shapepress::simulate {

// One contact per lane, the scalar law inlined: GCC vectorizes the loop once the law's branches
// (a spring to turn, a contact sliding, rolling friction) are if-converted, which this file's
// -fno-trapping-math permits, and its square roots need no errno test (-fno-math-errno,
// simulate/CMakeLists.txt). Neither flag changes a result: both sides of every branch are IEEE
// operations on the same values, and each lane keeps the side the scalar code takes. The file's
// -ffp-contract=off keeps the AVX-512 clone from fusing a multiply and an add into one rounding
// (its FMA instructions come with AVX-512F; the baseline and AVX2 code have none).
// `constants` is copied: the block's stores cannot reach a local, so the law's loads of it, some
// under a condition (the multi-contact law's given k1), need no check against them.
template <class Law>
[[gnu::always_inline]] inline void contact_block_lanes(ContactBlock& b, int count,
                                                       const PairConstants& constants, double dt) {
  const PairConstants pair = constants;
  for (int l = 0; l < count; ++l) {
    const double d[3] = {b.separation[0][l], b.separation[1][l], b.separation[2][l]};
    const PairEnd first{{b.velocity_first[0][l], b.velocity_first[1][l], b.velocity_first[2][l]},
                        {b.spin_first[0][l], b.spin_first[1][l], b.spin_first[2][l]},
                        b.mass_first[l],
                        b.inverse_inertia_first[l]};
    const PairEnd second{
        {b.velocity_second[0][l], b.velocity_second[1][l], b.velocity_second[2][l]},
        {b.spin_second[0][l], b.spin_second[1][l], b.spin_second[2][l]},
        b.mass_second[l],
        b.inverse_inertia_second[l]};
    PairKinematics k = pair_kinematics(d, b.radius_first[l], b.radius_second[l], first, second);
    if (b.body_radius[l] > 0.0) k.contact.effective_radius = b.body_radius[l];
    ContactHistory history;
    for (int axis = 0; axis < 3; ++axis)
      history.tangential[axis] = b.spring[axis][l];
    if constexpr (std::is_same_v<Law, MulticontactLaw>) {
      k.contact.pair_pressure = b.pair_pressure[l];
      plastic_force(history) = b.plastic_force[l];
    }
    const ContactForce f = contact_force<Law>(k.contact, pair, history, dt);
    double torque_first[3], torque_second[3];
    contact_torques(k.contact.normal, f, k.arm_first, k.arm_second, torque_first, torque_second);
    for (int axis = 0; axis < 3; ++axis) {
      b.spring[axis][l] = history.tangential[axis];
      b.force[axis][l] = f.force[axis];
      b.torque_first[axis][l] = torque_first[axis];
      b.torque_second[axis][l] = torque_second[axis];
    }
    if constexpr (std::is_same_v<Law, MulticontactLaw>) b.plastic_force[l] = plastic_force(history);
    b.normal_force[l] = f.normal_force;
    b.overlap[l] = k.contact.overlap;
  }
}

// The clones are plain functions: GCC does not vectorize a function template's clones.
__attribute__((target_clones("avx512f", "avx2", "default"))) void hertz_contact_block(
    ContactBlock& block, int count, const PairConstants& pair, double dt) {
  contact_block_lanes<HertzLaw>(block, count, pair, dt);
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void multicontact_contact_block(
    ContactBlock& block, int count, const PairConstants& pair, double dt) {
  contact_block_lanes<MulticontactLaw>(block, count, pair, dt);
}

}  // namespace shapepress::simulate
