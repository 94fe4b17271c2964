#!/usr/bin/env python3
"""A generated robot's Python module (mbgen generate --python, mbgen_add_robot(... PYTHON)) against
relations between its functions that a wrong binding breaks: a transposed matrix, a misplaced
output, a batch row taken from the wrong state, a shape not checked. MBGEN_MODULE names the
module, found on PYTHONPATH (tests/CMakeLists.txt: mbgen_add_python_module_test).

Tolerances: identities of exact algebra (M a against ID(a) - ID(0), a solve against NumPy's) to
1e-10 relative; derivatives against central finite differences (h = 1e-5) to 1e-6 relative to the
largest entry (their truncation and round-off errors, ~1e-16 / h + h^2, relative)."""
import importlib
import os
import threading
import unittest

import numpy as np

robot = importlib.import_module(os.environ["MBGEN_MODULE"])
FD_STEP = 1e-5
FD_TOLERANCE = 1e-6
EXACT = 1e-10


def relative_error(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(1.0, np.max(np.abs(b)))


def joint_coordinates():
    """(q index, v index) of the 1-DoF joints after a floating base: plain partial derivatives."""
    first = 6 if robot.floating_base else 0
    shift = 1 if robot.floating_base else 0
    return [(k + shift, k) for k in range(first, robot.nv)]


def random_state(seed):
    """A seeded random pose near the nominal one (loops: closed), velocities and forces. With loops
    the independent coordinates move by up to 0.05 rad or a tenth of their range (Lola's knee nut
    travels millimetres), in ten steps that Newton follows from the last closed pose, as
    tests/test_support.hpp's consistent_state does; the nominal pose q = 0 is the shipped robots'
    assembled one."""
    rng = np.random.default_rng(seed)
    q = np.zeros(robot.nq)
    if robot.floating_base:
        q[6] = 1.0
    if robot.has_loops:
        ranges = dict(zip(robot.limited_q_index, zip(robot.limited_lower, robot.limited_upper)))
        target = q.copy()
        shift = 1 if robot.floating_base else 0
        for vi in robot.independent_v_index:
            qi = vi + shift
            if robot.floating_base and vi < 6:
                continue
            lower, upper = ranges.get(qi, (-np.inf, np.inf))
            spread = min(0.05, 0.1 * (upper - lower))
            target[qi] = np.clip(rng.uniform(-spread, spread), lower, upper)
        start = q.copy()
        for step in range(1, 11):
            q[7 if robot.floating_base else 0:] = (start + (target - start) * step / 10)[7 if robot.floating_base else 0:]
            q, result = robot.closure_positions(q)
            assert result.status == robot.ClosureStatus.converged, result
    else:
        for qi, _ in joint_coordinates():
            q[qi] = rng.uniform(-0.4, 0.4)
    if robot.floating_base:
        q[:3] = rng.uniform(-0.5, 0.5, 3)
        quaternion = rng.normal(size=4)
        q[3:7] = quaternion / np.linalg.norm(quaternion)
    vy = rng.uniform(-1.0, 1.0, robot.ny)
    tau = rng.uniform(-5.0, 5.0, robot.nv)
    return q, vy, tau


def central_difference(function, x, columns, offset_of=lambda k: k):
    """Columns of d function / d x by central differences, for the entries `columns` of x."""
    out = []
    for k in columns:
        plus, minus = x.copy(), x.copy()
        plus[offset_of(k)] += FD_STEP
        minus[offset_of(k)] -= FD_STEP
        out.append((function(plus) - function(minus)) / (2 * FD_STEP))
    return np.stack(out, axis=-1)


def full_velocities(q, vy):
    return robot.full_velocities(q, vy) if robot.has_loops else vy


class Tables(unittest.TestCase):
    def test_sizes_match_the_tables(self):
        self.assertEqual(len(robot.independent_joint_names), robot.ny)
        self.assertEqual(len(robot.independent_v_index), robot.ny)
        self.assertEqual(len(robot.actuated_joint_names), robot.na)
        self.assertEqual(len(robot.body_names), robot.num_bodies)
        self.assertEqual(len(robot.frame_names), robot.num_frames)
        self.assertEqual(len(robot.distance_pair_names), robot.num_distance_pairs)
        self.assertEqual(len(robot.limited_joint_names), robot.num_limited_joints)
        self.assertTrue(np.all(robot.limited_lower <= robot.limited_upper))
        self.assertEqual(robot.has_loops, robot.ny < robot.nv)
        for first, second in robot.distance_pair_names:
            self.assertIn(first, robot.body_names)
            self.assertIn(second, robot.body_names)


class Dynamics(unittest.TestCase):
    def setUp(self):
        self.q, self.vy, self.tau = random_state(1)
        self.v = full_velocities(self.q, self.vy)

    def test_mass_matrix_is_the_inverse_dynamics_linear_part(self):
        # The spanning tree's: M a = ID(q, v, a) - ID(q, v, 0) for every a; M symmetric positive definite.
        M = robot.mass_matrix(self.q)
        self.assertEqual(M.shape, (robot.nv, robot.nv))
        a = np.random.default_rng(2).uniform(-1, 1, robot.nv)
        bias = robot.inverse_dynamics(self.q, self.v, np.zeros(robot.nv))
        self.assertLess(relative_error(M @ a, robot.inverse_dynamics(self.q, self.v, a) - bias), EXACT)
        self.assertLess(relative_error(M, M.T), 1e-14)
        np.linalg.cholesky(M)

    def test_mass_matrix_solve_is_numpys(self):
        M = robot.mass_matrix(self.q)
        LD = robot.mass_matrix_factor(M)
        self.assertLess(relative_error(robot.mass_matrix_solve(LD, self.tau), np.linalg.solve(M, self.tau)), EXACT)

    def test_forward_dynamics_satisfies_the_equations_of_motion(self):
        if not robot.has_loops:
            qdd = robot.forward_dynamics(self.q, self.v, self.tau)
            self.assertLess(relative_error(robot.inverse_dynamics(self.q, self.v, qdd), self.tau), EXACT)
            return
        # Closed loops: the full accelerations keep the closures' accelerations at zero (J qdd = gamma),
        # and the velocity map T spans J's null space.
        qdd = robot.full_accelerations(self.q, self.vy, self.tau)
        Phi, J, gamma = robot.closure_constraints(self.q, self.v)
        self.assertLess(np.max(np.abs(Phi)), 1e-10)
        self.assertLess(relative_error(J @ qdd, gamma), 1e-9)
        T = robot.velocity_map(self.q)
        self.assertEqual(T.shape, (robot.nv, robot.ny))
        self.assertLess(np.max(np.abs(J @ T)), 1e-10)
        ydd = robot.forward_dynamics(self.q, self.vy, self.tau)
        self.assertLess(relative_error(qdd, T @ ydd + robot.acceleration_bias(self.q, self.vy)), 1e-9)


class Kinematics(unittest.TestCase):
    def setUp(self):
        self.q, _, _ = random_state(3)
        self.columns = joint_coordinates()

    def test_frame_jacobians_are_the_derivatives_of_the_frame_poses(self):
        if robot.num_frames == 0:
            self.skipTest("no frames")
        J = robot.frame_jacobians(self.q)
        X = robot.frame_poses(self.q)
        self.assertEqual(J.shape, (robot.num_frames, 6, robot.nv))
        self.assertEqual(X.shape, (robot.num_frames, 3, 4))
        dX = central_difference(lambda q: robot.frame_poses(q), self.q, [qi for qi, _ in self.columns])
        for f in range(robot.num_frames):
            for c, (_, vi) in enumerate(self.columns):
                linear = dX[f, :, 3, c]
                W = dX[f, :, :3, c] @ X[f, :, :3].T  # dR R^T = [w]x
                angular = np.array([W[2, 1], W[0, 2], W[1, 0]])
                self.assertLess(relative_error(J[f, :3, vi], linear), FD_TOLERANCE)
                self.assertLess(relative_error(J[f, 3:, vi], angular), FD_TOLERANCE)

    def test_frames_on_bodies_have_the_bodies_poses(self):
        X_WB = robot.forward_kinematics(self.q)
        X_WF = robot.frame_poses(self.q)
        for f, name in enumerate(robot.frame_names):
            if name in robot.body_names:
                self.assertLess(relative_error(X_WF[f], X_WB[robot.body_names.index(name)]), 1e-14)

    def test_centroidal_momentum_matrix_moves_the_centre_of_mass(self):
        if not robot.floating_base:
            self.skipTest("the mass is read off the floating base's columns")
        Ag = robot.centroidal_momentum_matrix(self.q)
        mass = np.linalg.norm(Ag[:3, 0])  # the base's linear velocity moves the whole mass: m R
        dcom = central_difference(lambda q: robot.center_of_mass(q), self.q, [qi for qi, _ in self.columns])
        self.assertLess(relative_error(Ag[:3, [vi for _, vi in self.columns]] / mass, dcom), FD_TOLERANCE)

    def test_task_kinematics_is_the_four_functions(self):
        X, J, com, Ag = robot.task_kinematics(self.q)
        # One pass for the four: the same values, summed in another order.
        self.assertLess(relative_error(X, robot.frame_poses(self.q)), 1e-14)
        self.assertLess(relative_error(J, robot.frame_jacobians(self.q)), 1e-14)
        self.assertLess(relative_error(com, robot.center_of_mass(self.q)), 1e-14)
        self.assertLess(relative_error(Ag, robot.centroidal_momentum_matrix(self.q)), 1e-14)


class Derivatives(unittest.TestCase):
    def setUp(self):
        if not hasattr(robot, "forward_dynamics_derivatives"):
            self.skipTest("generated without fd_derivatives")
        if robot.has_loops:
            self.skipTest("closed-loop derivatives are in the independent coordinates (C++ tests)")
        self.q, self.v, self.tau = random_state(4)
        self.columns = joint_coordinates()

    def test_forward_dynamics_derivatives_against_finite_differences(self):
        qdd, dq, dv, Minv = robot.forward_dynamics_derivatives(self.q, self.v, self.tau)
        self.assertLess(relative_error(qdd, robot.forward_dynamics(self.q, self.v, self.tau)), 1e-12)
        self.assertLess(relative_error(Minv @ robot.mass_matrix(self.q), np.eye(robot.nv)), EXACT)
        fd_v = central_difference(lambda v: robot.forward_dynamics(self.q, v, self.tau), self.v, range(robot.nv))
        self.assertLess(relative_error(dv, fd_v), FD_TOLERANCE)
        fd_q = central_difference(lambda q: robot.forward_dynamics(q, self.v, self.tau), self.q,
                                  [qi for qi, _ in self.columns])
        self.assertLess(relative_error(dq[:, [vi for _, vi in self.columns]], fd_q), FD_TOLERANCE)

    def test_inverse_dynamics_derivatives_against_finite_differences(self):
        a = self.tau / 10
        tau, dq, dv = robot.inverse_dynamics_derivatives(self.q, self.v, a)
        self.assertLess(relative_error(tau, robot.inverse_dynamics(self.q, self.v, a)), 1e-12)
        fd_v = central_difference(lambda v: robot.inverse_dynamics(self.q, v, a), self.v, range(robot.nv))
        self.assertLess(relative_error(dv, fd_v), FD_TOLERANCE)
        fd_q = central_difference(lambda q: robot.inverse_dynamics(q, self.v, a), self.q, [qi for qi, _ in self.columns])
        self.assertLess(relative_error(dq[:, [vi for _, vi in self.columns]], fd_q), FD_TOLERANCE)


class Closures(unittest.TestCase):
    def setUp(self):
        if not robot.has_loops:
            self.skipTest("no loops")

    def test_closure_positions_closes_and_holds_the_independent_coordinates(self):
        q, vy, _ = random_state(5)
        # The dependent coordinates moved off the closed pose.
        opened = q.copy()
        shift = 1 if robot.floating_base else 0
        rng = np.random.default_rng(6)
        for qi, vi in joint_coordinates():
            if vi not in robot.independent_v_index:
                opened[qi] += rng.uniform(-0.01, 0.01)
        closed, result = robot.closure_positions(opened)
        self.assertEqual(result.status, robot.ClosureStatus.converged)
        self.assertGreater(result.iterations, 0)
        Phi, _, _ = robot.closure_constraints(closed, np.zeros(robot.nv))
        self.assertLess(np.max(np.abs(Phi)), 1e-10)
        self.assertLessEqual(result.residual, 1e-12)
        for vi in robot.independent_v_index:
            if vi >= (6 if robot.floating_base else 0):
                self.assertEqual(closed[vi + shift], opened[vi + shift])
        self.assertFalse(np.array_equal(opened, closed))  # the input is left as it was

    def test_close_loops_makes_the_velocities_consistent(self):
        q, vy, _ = random_state(7)
        v = np.random.default_rng(8).uniform(-1, 1, robot.nv)
        closed, consistent, result = robot.close_loops(q, v)
        self.assertEqual(result.status, robot.ClosureStatus.converged)
        _, J, _ = robot.closure_constraints(closed, consistent)
        self.assertLess(np.max(np.abs(J @ consistent)), 1e-10)
        np.testing.assert_array_equal(consistent[robot.independent_v_index], v[robot.independent_v_index])


    def test_a_nan_position_is_reported_not_converged(self):
        q, _, _ = random_state(6)
        q[-1] = np.nan
        closed, result = robot.closure_positions(q)
        self.assertEqual(result.status, robot.ClosureStatus.not_converged)
        self.assertTrue(np.isnan(closed[-1]))  # the input as it was: nothing made up


class Distances(unittest.TestCase):
    def setUp(self):
        if not hasattr(robot, "self_distances") or robot.num_distance_pairs == 0:
            self.skipTest("no self-distance pairs")
        self.q, _, _ = random_state(9)

    def test_witness_points_normals_and_jacobian(self):
        distance, normal, witness, jacobian = robot.self_distances(self.q)
        P = robot.num_distance_pairs
        self.assertEqual((distance.shape, normal.shape, witness.shape, jacobian.shape),
                         ((P,), (P, 3), (P, 6), (P, robot.nv)))
        self.assertLess(relative_error(witness[:, 3:] - witness[:, :3], distance[:, None] * normal), 1e-12)
        self.assertLess(relative_error(np.linalg.norm(normal, axis=1), np.ones(P)), 1e-12)
        # Along a motion of the joints: d distance = jacobian dv.
        dv = np.zeros(robot.nv)
        direction = np.random.default_rng(10).uniform(-1, 1, robot.nv)
        shift = 1 if robot.floating_base else 0
        moved = lambda h: self.q + np.concatenate([np.zeros(shift), h * dv])
        for qi, vi in joint_coordinates():
            dv[vi] = direction[vi]
        rate = (robot.self_distances(moved(FD_STEP))[0] - robot.self_distances(moved(-FD_STEP))[0]) / (2 * FD_STEP)
        self.assertLess(relative_error(jacobian @ dv, rate), 1e-5)

    def test_the_near_set_is_the_full_set_below_the_threshold(self):
        distance, normal, witness, jacobian = robot.self_distances(self.q)
        threshold = float(np.sort(distance)[len(distance) // 10])
        near_distance, near, near_normal, near_witness, near_jacobian = robot.self_distances_near(self.q, threshold)
        np.testing.assert_array_equal(near, np.flatnonzero(distance < threshold))
        np.testing.assert_array_equal(near_distance[near], distance[near])
        np.testing.assert_array_equal(near_normal, normal[near])
        np.testing.assert_array_equal(near_witness, witness[near])
        np.testing.assert_array_equal(near_jacobian, jacobian[near])
        self.assertTrue(np.all(near_distance >= np.minimum(distance, threshold) - 1e-12))


class Contact(unittest.TestCase):
    def setUp(self):
        if robot.num_contact_spheres == 0:
            self.skipTest("no contact spheres")
        self.q, self.vy, self.tau = random_state(11)
        self.v = full_velocities(self.q, self.vy)

    def lowered_until_touching(self, depth):
        p, _ = robot.contact_points(self.q)
        lowest = np.min(p[:, 2] - robot.contact_sphere_radius)
        q = self.q.copy()
        q[2] += robot.ground_offset - lowest - depth
        return q

    def test_apart_the_law_gives_nothing_and_the_free_accelerations(self):
        q = self.lowered_until_touching(-0.5)  # half a metre above the ground
        qdd, contacts = robot.contact_accelerations(q, self.v, self.tau, robot.default_ground, robot.default_law)
        self.assertEqual(contacts.shape, (robot.num_contact_spheres, 10))
        self.assertTrue(np.all(contacts[:, 0] <= 0))  # penetration: positive in contact
        np.testing.assert_array_equal(contacts[:, 4:7], 0.0)
        full = robot.full_accelerations(q, self.vy, self.tau) if robot.has_loops else robot.forward_dynamics(q, self.v, self.tau)
        self.assertLess(relative_error(qdd, full), EXACT)

    def test_in_contact_the_ground_pushes_up(self):
        q = self.lowered_until_touching(0.002)
        _, contacts = robot.contact_accelerations(q, np.zeros(robot.nv), self.tau, robot.default_ground, robot.default_law)
        touching = contacts[:, 0] > 0
        self.assertTrue(np.any(touching))
        self.assertTrue(np.all(contacts[touching, 6] > 0))
        np.testing.assert_array_equal(contacts[~touching, 4:7], 0.0)


def free_fall_error(make_simulator, functions):
    """Off the ground and with no force but gravity, the centre of mass moves as c0 + u t - g t^2 / 2
    whatever the joints do: the largest distance from that after 0.05 s of RK4 (1 ms steps), the
    centre of mass and its velocity u taken with `functions` (a module with center_of_mass and
    centroidal_momentum_matrix)."""
    q, vy, _ = random_state(400)
    v = full_velocities(q, 0.1 * vy)  # slow enough that Lola's knee nut stays inside its few mm of travel
    v[:6] = 0.0
    simulator = make_simulator()
    assert simulator.set_state(q, v) == "converged"
    start = functions.center_of_mass(simulator.q)
    Ag = functions.centroidal_momentum_matrix(simulator.q)
    mass = np.linalg.norm(Ag[:3, 0])  # the base's linear velocity moves the whole mass: m R
    velocity = (Ag @ simulator.v)[:3] / mass
    assert simulator.run_until(0.05) == "ok"
    t = simulator.time
    expected = start + velocity * t + np.array([0.0, 0.0, -9.81 * t * t / 2])
    return np.max(np.abs(functions.center_of_mass(simulator.q) - expected))


class Simulation(unittest.TestCase):
    def setUp(self):
        if not hasattr(robot, "Simulator"):
            self.skipTest("generated without the simulator's Backend")

    def test_a_free_fall_follows_the_closed_form(self):
        if not robot.floating_base:
            self.skipTest("a fixed base does not fall")
        make = lambda: robot.Simulator(contact=False, joint_stops=False, step=1e-3)
        self.assertLess(free_fall_error(make, robot), 1e-9)

    def test_a_nan_state_is_reported_by_status(self):
        q, _, _ = random_state(405)
        simulator = robot.Simulator(contact=False)
        bad = q.copy()
        bad[-1] = np.nan
        self.assertEqual(simulator.set_state(bad, np.zeros(robot.nv)), "not_converged" if robot.has_loops else "converged")
        v = np.zeros(robot.nv)
        v[-1] = np.nan
        simulator.set_state(q, v)
        self.assertEqual(simulator.step(), "diverged")

    def test_on_the_ground_the_law_pushes_up(self):
        if robot.num_contact_spheres == 0:
            self.skipTest("no contact spheres")
        q, _, _ = random_state(403)
        centres, _ = robot.contact_points(q)
        q[2] += robot.ground_offset - np.min(centres[:, 2] - robot.contact_sphere_radius) - 0.001
        simulator = robot.Simulator()
        simulator.set_state(q, np.zeros(robot.nv))
        contacts = simulator.contacts()
        self.assertEqual(contacts["force"].shape, (robot.num_contact_spheres, 3))
        self.assertTrue(np.any(contacts["active"]))
        self.assertTrue(np.all(contacts["force"][contacts["active"], 2] > 0))
        np.testing.assert_array_equal(contacts["active"], contacts["penetration"] > 0)


def integrate(q, dv):
    """q moved by the small tangent step dv, to first order in dv (the base's linear and angular
    velocity in its own axes, as the header states; quaternion x, y, z, w)."""
    out = np.array(q, dtype=float)
    if not robot.floating_base:
        return out + dv
    x, y, z, w = q[3:7]
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    out[0:3] += R @ dv[0:3]
    a, b, c = 0.5 * dv[3:6]
    quaternion = np.array([w * a + x + y * c - z * b, w * b + y + z * a - x * c, w * c + z + x * b - y * a,
                           w - x * a - y * b - z * c])  # (x, y, z, w) times (a, b, c, 1)
    out[3:7] = quaternion / np.linalg.norm(quaternion)
    out[7:] += dv[6:]
    return out


def ik_tasks(gain=10.0):
    """Position tasks on the first two frames and the centre of mass: 9 rows, regular at the test
    states (6-row pose tasks on Lola's straight legs are not)."""
    return [dict(name=f"frame{k}", kind="position", frame=robot.frame_names[k], gain=gain) for k in range(2)] + \
        [dict(name="com", kind="com", gain=gain)]


def set_ik_targets(ik, q, offset):
    """Each task's target `offset` (m) from where it is at q, with no feed-forward."""
    X = robot.frame_poses(q)
    for k in range(2):
        ik.set_target(f"frame{k}", position=X[k][:, 3] + offset)
    ik.set_target("com", position=robot.center_of_mass(q) + offset)


class Control(unittest.TestCase):
    """DifferentialIk on the generated Backend (mbgen/python/differential_ik_binding.hpp)."""
    EXACT_PSEUDO_INVERSE = dict(singular_region=0.0, max_damping=0.0)

    def setUp(self):
        if not hasattr(robot, "DifferentialIk"):
            self.skipTest("generated without the simulator's Backend")
        if len(robot.frame_names) < 2:
            self.skipTest("fewer than two frames")
        self.q = random_state(501)[0]

    def test_the_step_achieves_the_task_velocity_and_the_secondary_motion_keeps_it(self):
        offset = np.array([0.002, -0.001, 0.001])
        plain = robot.DifferentialIk(ik_tasks(), **self.EXACT_PSEUDO_INVERSE)
        secondary = robot.DifferentialIk(ik_tasks(), joint_limits=True, limit_activation=1e3,
                                         **self.EXACT_PSEUDO_INVERSE)  # every limited joint pushed
        steps = []
        for ik in (plain, secondary):
            set_ik_targets(ik, self.q, offset)
            v, report = ik.step(self.q)
            self.assertTrue(report["ok"])
            self.assertEqual(report["rank"], 9)
            J, xd = ik.primary_jacobian, ik.primary_velocity
            self.assertEqual(J.shape, (9, robot.nv))
            np.testing.assert_allclose(xd, np.tile(10.0 * offset, 3), rtol=0, atol=1e-12)  # gain * error
            self.assertLess(np.max(np.abs(J @ v - xd)), 1e-12 * np.max(np.abs(J)) * np.max(np.abs(v)))
            # The task rows are the generated Jacobians': the frames' linear rows and the CoM's.
            jacobians = robot.frame_jacobians(self.q)
            np.testing.assert_allclose(J[0:3], jacobians[0][0:3], rtol=0, atol=1e-12)
            np.testing.assert_allclose(J[3:6], jacobians[1][0:3], rtol=0, atol=1e-12)
            steps.append((v, report))
        self.assertEqual(steps[0][1]["active_limits"], 0)
        self.assertEqual(steps[1][1]["active_limits"], 2 * robot.num_limited_joints)  # both ends of each range
        self.assertGreater(np.max(np.abs(steps[1][0] - steps[0][0])), 1e-6)  # the potential moved something
        if robot.has_loops:  # v = T c: the loops stay closed to first order
            v = steps[1][0]
            np.testing.assert_allclose(robot.full_velocities(self.q, v[robot.independent_v_index]), v, rtol=0, atol=1e-12)

    def test_feed_forward_and_gain_make_the_task_velocity(self):
        ik = robot.DifferentialIk(ik_tasks(gain=0.0))
        set_ik_targets(ik, self.q, np.array([0.1, 0.1, 0.1]))  # no gain: the error does not count
        ik.set_target("frame1", velocity=[0.1, 0.2, 0.3])
        ik.set_target("com", velocity=[0.0, 0.0, -0.05])
        ik.step(self.q)
        np.testing.assert_array_equal(ik.primary_velocity, [0, 0, 0, 0.1, 0.2, 0.3, 0, 0, -0.05])
        np.testing.assert_allclose(ik.center_of_mass, robot.center_of_mass(self.q), rtol=0, atol=1e-14)

    def test_a_task_moves_along_a_walk_of_steps(self):
        # Integrating the steps at 1 kHz moves the CoM to its target: the error decays as exp(-gain t).
        ik = robot.DifferentialIk(ik_tasks(gain=20.0))
        q = self.q.copy()
        com_target = robot.center_of_mass(q) + [0.0, 0.0, -0.005]
        set_ik_targets(ik, q, np.zeros(3))
        ik.set_target("com", position=com_target)
        for _ in range(100):
            v, report = ik.step(q)
            self.assertTrue(report["ok"])
            q = integrate(q, v * 1e-3)
            if robot.has_loops:
                q, result = robot.closure_positions(q)
                self.assertEqual(result.status, robot.ClosureStatus.converged)
        error = np.linalg.norm(robot.center_of_mass(q) - com_target)
        self.assertLess(error, 0.005 * 1.2 * np.exp(-20.0 * 0.1))
        self.assertGreater(error, 0.005 * 0.8 * np.exp(-20.0 * 0.1))

    def test_bad_tasks_and_options_are_named(self):
        with self.assertRaisesRegex(ValueError, r"task 'x': frame 'no_such_frame' is not among the backend's frames"):
            robot.DifferentialIk([dict(name="x", kind="pose", frame="no_such_frame")])
        with self.assertRaisesRegex(ValueError, r"task 'x' has kind 'twist': pose, position, orientation or com"):
            robot.DifferentialIk([dict(name="x", kind="twist", frame=robot.frame_names[0])])
        with self.assertRaisesRegex(TypeError, r"unknown option 'colision_avoidance' \(the options: activation_distance"):
            robot.DifferentialIk(ik_tasks(), colision_avoidance=True)
        with self.assertRaisesRegex(ValueError, r"weights\[0\] = -1.000000 must be finite and > 0"):
            robot.DifferentialIk(ik_tasks(), weights=[-1.0] + [1.0] * (robot.ny - 1))
        ik = robot.DifferentialIk(ik_tasks())
        with self.assertRaisesRegex(ValueError, rf"DifferentialIk: q must have shape \({robot.nq},\)"):
            ik.step(self.q[:-1])
        with self.assertRaisesRegex(ValueError, r"DifferentialIk: rotation must have shape \(3, 3\)"):
            ik.set_target("frame0", rotation=np.eye(4))
        with self.assertRaisesRegex(KeyError, r"no task named 'nope'"):
            ik.set_target("nope", position=[0, 0, 0])
        q = self.q.copy()
        q[-1] = np.nan
        v, report = ik.step(q)  # the step reports, it does not raise
        self.assertFalse(report["ok"])
        np.testing.assert_array_equal(v, np.zeros(robot.nv))


class Calls(unittest.TestCase):
    def setUp(self):
        self.states = [random_state(20 + k) for k in range(3)]

    def test_a_batch_equals_one_call_per_state(self):
        # 2 W + 1 states (W = batch_width, 4 without --batch): with --batch, two groups through the
        # batch functions and one state through the one-state function; bit for bit either way.
        count = 2 * max(robot.batch_width, 4) + 1
        states = self.states + [random_state(30 + k) for k in range(count - 3)]
        Q = np.stack([s[0] for s in states])
        V = np.stack([s[1] for s in states])
        tau = states[0][2]  # not batched: the same for every state
        QDD = robot.forward_dynamics(Q, V, tau)
        self.assertEqual(QDD.shape, (count, robot.ny))
        for k in range(count):
            np.testing.assert_array_equal(QDD[k], robot.forward_dynamics(Q[k], V[k], tau))
        M = robot.mass_matrix(Q)
        self.assertEqual(M.shape, (count, robot.nv, robot.nv))
        for k in range(count):
            np.testing.assert_array_equal(M[k], robot.mass_matrix(Q[k]))
        if robot.batch_width:  # the docstring says which functions run through their batch form
            self.assertIn(f"through forward_dynamics_batch", robot.forward_dynamics.__doc__)
            self.assertNotIn("_batch", robot.closure_positions.__doc__)
        empty = robot.mass_matrix(np.zeros((0, robot.nq)))
        self.assertEqual(empty.shape, (0, robot.nv, robot.nv))

    def test_lists_and_strided_views_are_converted(self):
        q, vy, tau = self.states[0]
        expected = robot.forward_dynamics(q, vy, tau)
        np.testing.assert_array_equal(robot.forward_dynamics(list(q), list(vy), list(tau)), expected)
        wide = np.zeros((robot.nq, 2))
        wide[:, 0] = q
        np.testing.assert_array_equal(robot.forward_dynamics(wide[:, 0], vy, tau), expected)
        np.testing.assert_array_equal(robot.forward_dynamics(q.astype(np.float32).astype(np.float64), vy, tau),
                                      robot.forward_dynamics(q.astype(np.float32), vy, tau))

    def test_threads_share_the_functions(self):
        Q = np.stack([s[0] for s in self.states] * 50)
        V = np.stack([s[1] for s in self.states] * 50)
        expected = robot.forward_dynamics(Q, V, self.states[0][2])
        results = [None] * 4

        def work(k):
            results[k] = robot.forward_dynamics(Q, V, self.states[0][2])

        threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for r in results:
            np.testing.assert_array_equal(r, expected)

    def test_every_function_documents_its_shapes_and_units(self):
        functions = [name for name in dir(robot) if not name.startswith("_") and type(getattr(robot, name)).__name__ ==
                     "builtin_function_or_method"]
        self.assertGreater(len(functions), 10)
        for name in functions:
            doc = getattr(robot, name).__doc__
            self.assertIn("Arguments:", doc, name)
            if name not in ("closure_positions", "close_loops", "self_distances", "self_distances_near"):
                self.assertIn("Units (SI", doc, name)
            self.assertRegex(doc, r"\n  \w+ \(\d+(, \d+)*,?\): ", name)  # an argument with its NumPy shape
            self.assertNotRegex(doc, r"\[\d+ x \d+", name)  # the C++ sizes are replaced by NumPy shapes
        self.assertIn(f"M ({robot.nv}, {robot.nv}): mass matrix", robot.mass_matrix.__doc__)
        if robot.num_frames:
            self.assertIn(f"X_WF ({robot.num_frames}, 3, 4)", robot.frame_poses.__doc__)
        for cls in [c for c in ("Simulator", "DifferentialIk") if hasattr(robot, c)]:
            for method in ("step", "__init__"):
                self.assertTrue(getattr(getattr(robot, cls), method).__doc__, f"{cls}.{method}")

    def test_bad_arguments_are_named(self):
        q, vy, tau = self.states[0]
        with self.assertRaisesRegex(ValueError, rf"forward_dynamics: q must have shape \({robot.nq},\) or "
                                                rf"\(N, {robot.nq}\) \(a batch of N\), not \({robot.nq - 1},\)"):
            robot.forward_dynamics(q[:-1], vy, tau)
        with self.assertRaisesRegex(ValueError, r"mass_matrix_solve: LD must have shape"):
            robot.mass_matrix_solve(np.zeros(robot.nv * robot.nv), tau)
        with self.assertRaisesRegex(ValueError, r"v holds 3 states, but q holds 2"):
            robot.forward_dynamics(np.stack([q, q]), np.stack([vy, vy, vy]), tau)
        with self.assertRaisesRegex(ValueError, r"closure_positions takes one state at a time"):
            robot.closure_positions(np.stack([q, q]))
        with self.assertRaisesRegex(TypeError, r"forward_dynamics: q must be an array of numbers \(float64\), not str"):
            robot.forward_dynamics("q", vy, tau)
        with self.assertRaisesRegex(TypeError, r"forward_dynamics: tau is None"):
            robot.forward_dynamics(q, vy, None)


if __name__ == "__main__":
    unittest.main(verbosity=2)
