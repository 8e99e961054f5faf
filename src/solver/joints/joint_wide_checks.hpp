#pragma once
// The joint kernels' double-lane pieces exposed for tests (joint_wide.hpp
// has the atan2 one; kept apart so that adding one does not rebuild every
// file that includes the joint solver).
#include <cstddef>

#include "fulcrum/math.hpp"
#include "solver/contact_wide.hpp"  // SimdPath

namespace fulcrum::detail {

// The hinge blocks' coupling solve (coupledInverseMass's bits in lanes of
// doubles, float in and out as coupleHingeRow uses it) over n systems, for
// tests: system s reads K[15 s ..] (K_oo's lower triangle by rows), Kia[5 s ..]
// (K_oa) and kaa[s], writes ok[s] and where ok c[5 s ..] and schur[s]. False
// (nothing written) where the path has no double lanes.
bool wideCoupledInverseMass(SimdPath path, const Real* K, const Real* Kia, const Real* kaa, Real* c, Real* schur,
                            bool* ok, std::size_t n);
bool avx2JointCoupledInverseMass(const Real* K, const Real* Kia, const Real* kaa, Real* c, Real* schur, bool* ok,
                                 std::size_t n);

}  // namespace fulcrum::detail
