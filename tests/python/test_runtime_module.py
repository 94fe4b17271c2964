#!/usr/bin/env python3
"""The mbgen package (python/mbgen: load() and the generic runtime, inspect(), generate()) against a
generated module of the same robot, built by the test build (MBGEN_MODULE, from MBGEN_DESCRIPTION,
MBGEN_EXTRAS, MBGEN_BASE into MBGEN_GENERATED_DIR; tests/CMakeLists.txt).

The generated code is traced from the generic code, so the two agree to round-off: 1e-12 relative,
the C++ suite's tolerance (tests/test_generated.cpp). The floating base's derivative columns, which
no finite difference of q's raw entries reaches, are checked through integrate()."""
import filecmp
import importlib
import os
import tempfile
import unittest

import numpy as np

import mbgen
from test_generated_module import (central_difference, free_fall_error, full_velocities, ik_tasks, joint_coordinates,
                                   random_state, relative_error, set_ik_targets)

generated = importlib.import_module(os.environ["MBGEN_MODULE"])
DESCRIPTION = os.environ["MBGEN_DESCRIPTION"]
EXTRAS = os.environ.get("MBGEN_EXTRAS") or None
BASE = os.environ["MBGEN_BASE"]
ROUND_OFF = 1e-12

# How tests/CMakeLists.txt generates each module (mbgen_add_robot's arguments as generate()'s).
GENERATION = {
    "lola": dict(name="lola", scalar="both", outputs=["all"], python=True),
    "solo12": dict(name="solo12", scalar="double", outputs=["all", "fd_derivatives", "id_derivatives"], batch=4,
                   python=True),
}

robot = mbgen.load(DESCRIPTION, extras=EXTRAS, base=BASE)


class Tables(unittest.TestCase):
    def test_the_loaded_robot_is_the_generated_one(self):
        for name in ("nq", "nv", "ny", "na", "num_bodies", "floating_base", "has_loops"):
            self.assertEqual(getattr(robot, name), getattr(generated, name), name)
        for name in ("joint_names", "body_names", "independent_joint_names", "actuated_joint_names"):
            self.assertEqual(list(getattr(robot, name)), list(getattr(generated, name)), name)
        np.testing.assert_array_equal(robot.independent_v_index, generated.independent_v_index)
        np.testing.assert_array_equal(robot.actuated_v_index, generated.actuated_v_index)

    def test_the_assembled_pose_is_closed(self):
        q, result = robot.closure_positions(robot.assembled_q)
        self.assertEqual(result["status"], "converged")
        self.assertLessEqual(result["residual"], 1e-12)


class GenericEqualsGenerated(unittest.TestCase):
    def test_every_common_function(self):
        functions = {
            "forward_dynamics": lambda m, q, vy, tau, v: m.forward_dynamics(q, vy, tau),
            "full_accelerations": lambda m, q, vy, tau, v: m.full_accelerations(q, vy, tau),
            "inverse_dynamics": lambda m, q, vy, tau, v: m.inverse_dynamics(q, v, tau / 10),
            "mass_matrix": lambda m, q, vy, tau, v: m.mass_matrix(q),
            "forward_kinematics": lambda m, q, vy, tau, v: m.forward_kinematics(q),
            "center_of_mass": lambda m, q, vy, tau, v: m.center_of_mass(q),
            "centroidal_momentum_matrix": lambda m, q, vy, tau, v: m.centroidal_momentum_matrix(q),
            "velocity_map": lambda m, q, vy, tau, v: m.velocity_map(q),
            "full_velocities": lambda m, q, vy, tau, v: m.full_velocities(q, vy),
        }
        for seed in range(5):
            q, vy, tau = random_state(100 + seed)
            v = generated.full_velocities(q, vy)
            for name, call in functions.items():
                with self.subTest(function=name, state=seed):
                    expected = call(robot, q, vy, tau, v)
                    self.assertEqual(np.shape(expected), np.shape(call(generated, q, vy, tau, v)))
                    self.assertLess(relative_error(call(generated, q, vy, tau, v), expected), ROUND_OFF)

    def test_closure_positions(self):
        if not robot.has_loops:
            self.skipTest("no loops")
        q, _, _ = random_state(200)
        opened = q.copy()
        for qi, vi in joint_coordinates():
            if vi not in robot.independent_v_index:
                opened[qi] += 0.005
        closed_generic, result = robot.closure_positions(opened)
        closed_generated, generated_result = generated.closure_positions(opened)
        self.assertEqual(result["status"], "converged")
        self.assertEqual(generated_result.status, generated.ClosureStatus.converged)
        self.assertLess(relative_error(closed_generated, closed_generic), ROUND_OFF)


class TangentConvention(unittest.TestCase):
    def test_difference_inverts_integrate(self):
        q, _, _ = random_state(300)
        v = np.random.default_rng(301).uniform(-0.5, 0.5, robot.nv)
        self.assertLess(relative_error(robot.difference(q, robot.integrate(q, v)), v), ROUND_OFF)

    def test_derivatives_of_every_column_along_integrate(self):
        if not hasattr(generated, "forward_dynamics_derivatives") or robot.has_loops:
            self.skipTest("generated without the tree's fd_derivatives")
        q, v, tau = random_state(302)
        _, dq, _, _ = generated.forward_dynamics_derivatives(q, v, tau)
        # d qdd / dq along q (+) delta, every column (the floating base's six included).
        along = central_difference(lambda delta: generated.forward_dynamics(robot.integrate(q, delta), v, tau),
                                   np.zeros(robot.nv), range(robot.nv))
        self.assertLess(relative_error(dq, along), 1e-6)


class Simulation(unittest.TestCase):
    def test_a_free_fall_follows_the_closed_form(self):
        if not robot.floating_base:
            self.skipTest("a fixed base does not fall")
        make = lambda: mbgen.Simulator(robot, contact=False, joint_stops=False, step=1e-3)
        self.assertLess(free_fall_error(make, robot), 1e-9)

    def test_the_generated_simulator_follows_the_generic_one(self):
        # The same start (on the ground when the scene has contact), both backends, RK4: the
        # generated and generic accelerations agree to round-off at every evaluation. End stops
        # off: the generated module has the runtime's default law, the Robot its scene's.
        if not hasattr(generated, "Simulator"):
            self.skipTest("generated without the simulator's Backend")
        q, vy, _ = random_state(404)
        if generated.num_contact_spheres:
            centres, _ = generated.contact_points(q)
            q[2] += generated.ground_offset - np.min(centres[:, 2] - generated.contact_sphere_radius) - 0.001
        v = full_velocities(q, 0.1 * vy)  # slow enough that Lola's knee nut stays inside its few mm of travel
        runs = [generated.Simulator(joint_stops=False), mbgen.Simulator(robot, joint_stops=False)]
        for simulator in runs:
            simulator.set_state(q, v)
            if generated.num_contact_spheres:
                self.assertTrue(np.any(simulator.contacts()["active"]))  # the ground pushes from the start
            self.assertEqual(simulator.run_until(0.02), "ok")
        self.assertGreater(runs[0].accepted_steps, 100)
        self.assertLess(relative_error(runs[0].q, runs[1].q), 1e-9, (runs[0].q - runs[1].q))
        self.assertLess(relative_error(runs[0].v, runs[1].v), 1e-7, (runs[0].v - runs[1].v))

    def simulators(self, **options):
        """The generic simulator and, when the module has one, the generated: both take the same options."""
        made = [("generic", lambda: mbgen.Simulator(robot, **options))]
        if hasattr(generated, "Simulator"):
            made.append(("generated", lambda: generated.Simulator(**options)))
        return made

    def test_a_step_advances_by_the_step_and_the_energy_is_kept(self):
        # Off the ground, no end stops, no controller: kinetic plus gravity energy is conserved
        # (RK4's error, ~1e-12 J here, and the loops' projection).
        q, vy, _ = random_state(405)
        v = full_velocities(q, 0.1 * vy)
        for name, make in self.simulators(contact=False, joint_stops=False, step=1e-4):
            with self.subTest(simulator=name):
                simulator = make()
                simulator.set_state(q, v)
                start = simulator.energy()
                self.assertEqual(simulator.step(), "ok")
                self.assertAlmostEqual(simulator.time, 1e-4, delta=1e-15)
                self.assertEqual(simulator.run_until(0.02), "ok")
                self.assertLess(abs(simulator.energy() - start), 1e-8 * max(1.0, abs(start)))

    def test_contact_false_lets_the_robot_fall_through_the_ground(self):
        if not generated.num_contact_spheres:
            self.skipTest("no contact spheres")
        q, _, _ = random_state(406)
        centres, _ = generated.contact_points(q)
        q[2] += generated.ground_offset - np.min(centres[:, 2] - generated.contact_sphere_radius) - 0.001
        fall = 9.81 * 0.01 ** 2 / 2
        for contact in (True, False):
            for name, make in self.simulators(contact=contact, step=1e-4):
                with self.subTest(simulator=name, contact=contact):
                    simulator = make()
                    simulator.set_state(q, np.zeros(robot.nv))
                    start = robot.center_of_mass(simulator.q)[2]
                    self.assertEqual(simulator.run_until(0.01), "ok")
                    drop = start - robot.center_of_mass(simulator.q)[2]
                    if contact:
                        self.assertLess(drop, fall - 1e-4)  # held up
                    else:
                        self.assertFalse(np.any(simulator.contacts()["active"]))
                        self.assertAlmostEqual(drop, fall, delta=1e-9)  # a free fall

    def test_joint_stops_push_a_joint_back_into_its_range(self):
        # An independent joint with a range, started past its upper end at rest: with the end
        # stops it is pushed back, without them it is not.
        shift = 1 if robot.floating_base else 0
        independent = set(int(v) for v in robot.independent_v_index)
        k = next(k for k in reversed(range(len(generated.limited_v_index)))
                 if int(generated.limited_v_index[k]) in independent)
        qi, vi = int(generated.limited_q_index[k]), int(generated.limited_v_index[k])
        self.assertEqual(qi, vi + shift)
        q, _, _ = random_state(407)
        q[qi] = generated.limited_upper[k] + 0.05 * (generated.limited_upper[k] - generated.limited_lower[k])
        for name, _ in self.simulators():
            with self.subTest(simulator=name):
                ends = []
                for stops in (True, False):
                    simulator = dict(self.simulators(contact=False, joint_stops=stops))[name]()
                    simulator.set_state(q, np.zeros(robot.nv))
                    self.assertEqual(simulator.run_until(0.01), "ok")
                    ends.append(simulator.v[vi])
                self.assertLess(ends[0], ends[1] - 1e-3)  # moving back down only with the stops

    def test_the_controller_is_called_and_its_size_checked(self):
        q, _, _ = random_state(402)
        calls = []
        simulator = mbgen.Simulator(robot, contact=False)
        simulator.set_controller(lambda t, q, v: calls.append(t) or np.zeros(robot.nv))
        simulator.set_state(q, np.zeros(robot.nv))
        simulator.run_until(0.01)
        self.assertGreaterEqual(len(calls), 10)  # every millisecond
        simulator.set_controller(lambda t, q, v: np.zeros(robot.nv + 1))
        with self.assertRaisesRegex(ValueError, f"it must return {robot.nv} joint forces, not {robot.nv + 1}"):
            simulator.run_until(0.02)

    def test_bad_options_are_named(self):
        with self.assertRaisesRegex(ValueError, "unknown integrator 'rk5'"):
            mbgen.Simulator(robot, integrator="rk5")
        with self.assertRaisesRegex(ValueError, "step must be positive"):
            mbgen.Simulator(robot, step=0.0)


class Control(unittest.TestCase):
    def test_the_generic_ik_takes_the_generated_ones_step(self):
        # Every secondary objective on: the joint ranges, the self-collision potential (the generic
        # Robot builds the scene's collision model as generate does: the same pairs), momentum.
        if not hasattr(generated, "DifferentialIk") or len(generated.frame_names) < 2:
            self.skipTest("generated without the Backend or its frames")
        options = dict(joint_limits=True, angular_momentum=True, momentum_axis_weights=(0.0, 0.0, 1.0))
        if generated.num_distance_pairs:
            options.update(collision_avoidance=True, activation_distance=0.2)
        q = random_state(502)[0]
        steps = []
        for ik in (mbgen.DifferentialIk(robot, ik_tasks(), **options), generated.DifferentialIk(ik_tasks(), **options)):
            set_ik_targets(ik, q, np.array([0.002, -0.001, 0.001]))
            ik.angular_momentum_target = [0.0, 0.0, 0.3]
            steps.append(ik.step(q))
            self.assertTrue(steps[-1][1]["ok"])
        self.assertEqual(steps[0][1], steps[1][1] | dict(smallest_singular_value=steps[0][1]["smallest_singular_value"]))
        if generated.num_distance_pairs:
            self.assertGreater(steps[0][1]["active_pairs"], 0)
        self.assertLess(relative_error(steps[0][0], steps[1][0]), ROUND_OFF)

    def test_a_task_names_a_frame_of_the_model(self):
        with self.assertRaisesRegex(ValueError, r"task 'x': no frame named 'no_such_frame' in model"):
            mbgen.DifferentialIk(robot, [dict(name="x", kind="pose", frame="no_such_frame")])
        with self.assertRaisesRegex(ValueError, r"DifferentialIk: a task needs a name"):
            mbgen.DifferentialIk(robot, [dict(kind="com")])
        with self.assertRaisesRegex(TypeError, r"a task has no key 'frmae'"):
            mbgen.DifferentialIk(robot, [dict(name="x", frmae="base")])


class Walking(unittest.TestCase):
    LEFT, RIGHT, COM = np.array([0.0, 0.1, 0.0]), np.array([0.0, -0.1, 0.0]), np.array([0.02, 0.0, 0.8])

    def test_the_pattern_starts_standing_and_ends_its_footsteps(self):
        pattern = mbgen.WalkingPattern(self.LEFT, self.RIGHT, self.COM, 0.001, steps=4, step_length=0.2, step_time=0.5,
                                       start_time=0.6, end_time=0.4)
        self.assertAlmostEqual(pattern.duration, 0.6 + 5 * 0.5 + 0.4, places=12)
        s = pattern.samples()
        n = pattern.num_samples
        self.assertEqual(s["foot"].shape, (n, 2, 3))
        self.assertEqual(s["com"].shape, (n, 3))
        np.testing.assert_allclose(s["t"], 0.001 * np.arange(n), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(s["foot"][0], [self.LEFT, self.RIGHT])
        np.testing.assert_allclose(s["com"][0, :2], self.COM[:2], rtol=0, atol=1e-3)
        footsteps = pattern.footsteps
        self.assertEqual(len(footsteps), 2 + 4 + 1)  # standing, four steps, the feet closed
        np.testing.assert_allclose(s["foot"][-1], [footsteps[-2]["position"], footsteps[-1]["position"]]
                                   if footsteps[-1]["foot"] == 1 else [footsteps[-1]["position"], footsteps[-2]["position"]])
        self.assertAlmostEqual(np.mean(s["foot"][-1][:, 0]), 3.5 * 0.2, places=12)  # 3 steps, then half a step
        self.assertEqual(set(np.unique(s["stance"])), {-1, 0, 1})
        # The swing foot lifts by step_height (default 5 cm) at mid-swing.
        self.assertAlmostEqual(np.max(s["foot"][:, :, 2]), 0.05, places=6)

    def test_correct_com_moves_the_com_by_the_pendulums_answer(self):
        pattern = mbgen.WalkingPattern(self.LEFT, self.RIGHT, self.COM, 0.001, steps=2)
        before = pattern.samples()["com"]
        pattern.correct_com(np.zeros((pattern.num_samples, 2)))
        np.testing.assert_array_equal(pattern.samples()["com"], before)
        error = np.zeros((pattern.num_samples, 2))
        error[:, 1] = 0.01  # the whole body's ZMP 1 cm left of the reference: the CoM moves right
        pattern.correct_com(error)
        # The pendulum's bounded answer to a constant -1 cm over [0, T] is -1 cm (1 - (e^-wt + e^-w(T-t)) / 2):
        # at the middle, -1 cm (1 - e^(-w T / 2)).
        middle = pattern.num_samples // 2
        expected = -0.01 * (1 - np.exp(-pattern.omega * pattern.samples()["t"][middle]))
        self.assertLess(abs(pattern.samples()["com"][middle, 1] - before[middle, 1] - expected), 2e-5)
        np.testing.assert_array_equal(pattern.samples()["com"][:, 0], before[:, 0])  # no error along x

    def test_bad_options_are_named(self):
        with self.assertRaisesRegex(TypeError, r"WalkingPattern: unknown option 'step_lenght' \(the options: steps, step_length"):
            mbgen.WalkingPattern(self.LEFT, self.RIGHT, self.COM, 0.001, step_lenght=0.3)
        with self.assertRaisesRegex(ValueError, r"needs dt > 0, step_time > double_support"):
            mbgen.WalkingPattern(self.LEFT, self.RIGHT, self.COM, 0.001, step_time=0.05, double_support=0.08)
        pattern = mbgen.WalkingPattern(self.LEFT, self.RIGHT, self.COM, 0.001, steps=1)
        with self.assertRaisesRegex(ValueError, r"zmp_error must have shape \(\d+, 2\)"):
            pattern.correct_com(np.zeros((3, 2)))
        with self.assertRaisesRegex(ValueError, r"the mass must be positive"):
            pattern.yaw_free_momentum(-1.0)


class Command(unittest.TestCase):
    def test_inspect_reports_the_robot(self):
        report = mbgen.inspect(DESCRIPTION, extras=EXTRAS, base=BASE)
        self.assertTrue(report["ok"])
        self.assertEqual((report["nq"], report["nv"]), (generated.nq, generated.nv))
        self.assertEqual(report["base"], BASE)

    def test_generate_writes_what_the_build_generated(self):
        with tempfile.TemporaryDirectory() as out:
            files = mbgen.generate(DESCRIPTION, out, extras=EXTRAS, base=BASE, **GENERATION[os.environ["MBGEN_MODULE"]])
            self.assertTrue(files[0].endswith(generated.__name__ + ".hpp"))
            built = os.environ["MBGEN_GENERATED_DIR"]
            self.assertEqual(sorted(os.listdir(out)), sorted(os.listdir(built)))
            for name in os.listdir(out):
                self.assertTrue(filecmp.cmp(os.path.join(out, name), os.path.join(built, name), shallow=False), name)

    def test_a_command_error_carries_the_message(self):
        with tempfile.TemporaryDirectory() as out:
            with self.assertRaisesRegex(mbgen.CommandError, "unknown output 'speed'"):
                mbgen.generate(DESCRIPTION, out, extras=EXTRAS, base=BASE, outputs=["speed"])


class BadInput(unittest.TestCase):
    def test_a_missing_file_is_a_load_error(self):
        with self.assertRaisesRegex(mbgen.LoadError, "no_such_robot.urdf"):
            mbgen.load("/nonexistent/no_such_robot.urdf")

    def test_a_negative_mass_is_a_load_error_naming_the_link(self):
        with tempfile.NamedTemporaryFile("w", suffix=".urdf") as urdf:
            urdf.write('<robot name="r"><link name="base"/><link name="arm"><inertial><mass value="-1"/>'
                       '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
                       '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
                       '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
            urdf.flush()
            with self.assertRaisesRegex(ValueError, "arm"):
                mbgen.load(urdf.name)

    def test_wrong_sizes_are_named(self):
        with self.assertRaisesRegex(ValueError, f"mass_matrix: q must have {robot.nq} entries, not 3"):
            robot.mass_matrix(np.zeros(3))
        with self.assertRaisesRegex(ValueError, "base must be 'floating' or 'fixed', not 'flying'"):
            mbgen.load(DESCRIPTION, base="flying")


if __name__ == "__main__":
    unittest.main(verbosity=2)
