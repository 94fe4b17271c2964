#pragma once
// The generic runtime's double algorithms that most tests call, instantiated once
// (runtime_instances.cpp, in mbgen_test_instances) rather than in every test file that calls
// them: when test_generated.cpp was still compiled once per robot of the suite, instantiating
// and optimising these took 40 % of each of those compilations (hyq at -O3: 18.6 s, 11.0 s with
// this header). Explicit instantiation declarations change no behaviour: the calls
// link to the one instance. A function templated on more than its scalar (an output type) is
// not here; it instantiates as before.
#include "mbgen/mbgen.hpp"

#ifndef MBGEN_TEST_INSTANCE
#define MBGEN_TEST_INSTANCE extern template
#endif

namespace mbgen {
namespace test_instances {
using V = ConstVecRef<double>;
}  // namespace test_instances

MBGEN_TEST_INSTANCE const VecX<double>& aba<double>(const Model&, Data<double>&, const test_instances::V&,
                                                    const test_instances::V&, const test_instances::V&);
MBGEN_TEST_INSTANCE const VecX<double>& rnea<double>(const Model&, Data<double>&, const test_instances::V&,
                                                     const test_instances::V&, const test_instances::V&);
MBGEN_TEST_INSTANCE const VecX<double>& nonlinear_effects<double>(const Model&, Data<double>&, const test_instances::V&,
                                                                  const test_instances::V&);
MBGEN_TEST_INSTANCE const MatX<double>& crba<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE const MatX<double>& mass_matrix_loops<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE void forward_dynamics_loops_independent<double>(const Model&, Data<double>&, const test_instances::V&,
                                                                    const test_instances::V&, const test_instances::V&);
MBGEN_TEST_INSTANCE const VecX<double>& inverse_dynamics_independent<double>(const Model&, Data<double>&, const test_instances::V&,
                                                                             const test_instances::V&, const test_instances::V&);
MBGEN_TEST_INSTANCE const Mat6X<double>& compute_joint_jacobians<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE const Mat6X<double>& centroidal_momentum_matrix<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE ClosureResult<double> closure_positions<double>(const Model&, Data<double>&, Eigen::Ref<VecX<double>>,
                                                                    const ClosureOptions&);
MBGEN_TEST_INSTANCE void forward_kinematics<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE void subsystem_velocity_maps<double>(const Model&, Data<double>&, const test_instances::V&);
MBGEN_TEST_INSTANCE void subsystem_acceleration_biases<double>(const Model&, Data<double>&, const test_instances::V&,
                                                               const test_instances::V&);

}  // namespace mbgen
