#!/usr/bin/env python3
"""Lola walks from Python: the walking pattern (mbgen.WalkingPattern) tracked at 1 kHz by the
differential IK on the generated backend (lola.DifferentialIk), with self-collision avoidance, the
joint-range potential and vertical angular-momentum tracking in the null space of the feet, CoM
and torso tasks; the loops closed again by the generated Newton after each step (docs/python.md,
docs/control.md "Walking": the same controller as mbgen_walk's "both" configuration).

    PYTHONPATH=build/examples:build/python python3 examples/python/lola_walk.py [--steps N] [--plot FILE.png] [--check]

--check verifies what the method guarantees, exit 1 if not: every step's velocity achieves the
primary task velocity whatever the secondary objectives add (|J v - xd| <= 1e-12 |J| |v|), the
loops close at every step, the feet follow the pattern within 1 mm and the CoM within 5 mm, no
pair of the legs comes closer than 1 cm, and the generic runtime's IK (mbgen.DifferentialIk)
takes the generated one's step to 1e-12 at sampled states. ctest's example.python_walk runs it."""
import argparse
import os
import sys
import time

import numpy as np

import lola
import mbgen

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DT = 1e-3
GAIN = 20.0
# The tasks of mbgen_walk (examples/walking/main.cpp, Planner::tasks): feet, CoM, torso orientation.
TASKS = [dict(name="left_foot", kind="pose", frame="foot_l", gain=GAIN),
         dict(name="right_foot", kind="pose", frame="foot_r", gain=GAIN),
         dict(name="com", kind="com", gain=GAIN),
         dict(name="torso", kind="orientation", frame="torso", gain=GAIN)]
# Its "both" configuration: avoidance (5 cm activation) and the vertical momentum, plus the ranges.
OPTIONS = dict(collision_avoidance=True, activation_distance=0.05, collision_stiffness=100.0, angular_momentum=True,
               momentum_weight=1e4, momentum_axis_weights=(0.0, 0.0, 1.0), joint_limits=True)
CROUCH = 0.04  # m the CoM goes down over the first half second (knees off the linkage's dead point)


def yaw(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def closed(q, what):
    q, result = lola.closure_positions(q)
    if result.status != lola.ClosureStatus.converged:
        sys.exit(f"lola_walk: the loops did not close {what} ({result})")
    return q


def start_pose(robot):
    """Bent knees (the assembled pose's straight legs are singular for the feet), the CoM moved over
    the feet's middle by the IK, every joint inside its range: mbgen_walk's start."""
    q = np.array(robot.assembled_q)
    for name in ("knee_act_l", "knee_act_r"):
        q[lola.limited_q_index[lola.limited_joint_names.index(name)]] = -0.02  # m of the knee nuts' travel: knees at 0.46 rad
    q = closed(q, "at the bent-knee pose")
    X = lola.frame_poses(q)
    assembled = lola.frame_poses(robot.assembled_q)
    ik = lola.DifferentialIk(TASKS)
    for k, name in enumerate(("left_foot", "right_foot")):
        ik.set_target(name, position=X[k][:, 3], rotation=assembled[k][:, :3])
    middle = 0.5 * (X[0][:, 3] + X[1][:, 3])
    ik.set_target("com", position=[middle[0], middle[1], lola.center_of_mass(q)[2]])
    ik.set_target("torso", rotation=X[2][:, :3])
    for _ in range(2000):
        v, report = ik.step(q)
        if not report["ok"]:
            sys.exit("lola_walk: the IK failed balancing the start posture")
        q = closed(robot.integrate(q, v * DT), "balancing the start posture")
    index = lola.limited_q_index
    q[index] = np.clip(q[index], lola.limited_lower, lola.limited_upper)
    return closed(q, "at the start pose")


def set_targets(ik, sample, k, R0, com0, momentum):
    """The pattern's references at sample k (mbgen_walk's Planner::step without the QP's release)."""
    s = sample
    for f, name in enumerate(("left_foot", "right_foot")):
        ik.set_target(name, position=s["foot"][k, f], rotation=yaw(s["foot_yaw"][k, f]) @ R0[f],
                      velocity=np.r_[s["foot_velocity"][k, f], 0.0, 0.0, s["foot_yaw_rate"][k, f]])
    t = s["t"][k]
    ramp = min(1.0, t / 0.5)
    com = np.array([s["com"][k, 0], s["com"][k, 1], com0[2] - CROUCH * ramp * ramp * (3 - 2 * ramp)])
    com_velocity = np.array(s["com_velocity"][k])
    com_velocity[2] = -CROUCH * 6 * ramp * (1 - ramp) / 0.5 if t < 0.5 else 0.0
    ik.set_target("com", position=com, velocity=com_velocity)
    ik.set_target("torso", rotation=yaw(s["heading"][k]) @ R0[2], velocity=[0.0, 0.0, s["heading_rate"][k]])
    ik.angular_momentum_target = [0.0, 0.0, momentum[k]]
    return com


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=6, help="steps of the walk (default 6)")
    parser.add_argument("--plot", help="write the walk's chart to this PNG (needs matplotlib)")
    parser.add_argument("--check", action="store_true", help="exit 1 unless the walk keeps what the method guarantees")
    args = parser.parse_args()

    robot = mbgen.load(os.path.join(ROOT, "robots/lola/lola.urdf"), extras=os.path.join(ROOT, "robots/lola/lola.yaml"),
                       base="floating")
    q = start_pose(robot)
    X = lola.frame_poses(q)
    R0 = [X[f][:, :3] for f in range(3)]
    com0 = lola.center_of_mass(q)
    pattern = mbgen.WalkingPattern(X[0][:, 3], X[1][:, 3], com0, DT, steps=args.steps)
    sample = pattern.samples()
    mass = lola.mass_matrix(q)[0, 0]  # the floating base's translational inertia: the total mass
    momentum = pattern.yaw_free_momentum(mass)
    ik = lola.DifferentialIk(TASKS, **OPTIONS)
    generic = mbgen.DifferentialIk(robot, TASKS, **OPTIONS) if args.check else None
    legs = [k for k, (a, b) in enumerate(lola.distance_pair_names) if a.endswith(("_l", "_r")) and b.endswith(("_l", "_r"))
            and a[-2:] != b[-2:]]
    # Below the hips (the hip links' pairs keep their distance but for the hips' yaw): what a step swings.
    lower_legs = [k for k in legs if not any(name.startswith("hip_") for name in lola.distance_pair_names[k])]

    n = pattern.num_samples
    log = {key: np.zeros(shape) for key, shape in
           dict(com=(n, 3), com_ref=(n, 3), feet=(n, 2, 3), leg_distance=n, lower_leg_distance=n, null_space=n,
                momentum=n).items()}
    failures = []
    start = time.perf_counter()
    for k in range(n):
        log["com_ref"][k] = set_targets(ik, sample, k, R0, com0, momentum)
        v, report = ik.step(q)
        if not report["ok"]:
            sys.exit(f"lola_walk: the IK failed at t = {sample['t'][k]:.3f} s")
        J = ik.primary_jacobian
        log["null_space"][k] = np.max(np.abs(J @ v - ik.primary_velocity)) / (np.max(np.abs(J)) * np.max(np.abs(v)))
        log["leg_distance"][k] = np.min(ik.distances[legs])
        log["lower_leg_distance"][k] = np.min(ik.distances[lower_legs])
        log["momentum"][k] = (lola.centroidal_momentum_matrix(q) @ v)[5]
        X = lola.frame_poses(q)
        log["feet"][k] = [X[0][:, 3], X[1][:, 3]]
        log["com"][k] = lola.center_of_mass(q)
        if generic is not None and k % 500 == 0:  # the generic runtime's IK, in the same state
            set_targets(generic, sample, k, R0, com0, momentum)
            v_generic, _ = generic.step(q)
            error = np.max(np.abs(v_generic - v)) / np.max(np.abs(v))
            if error > 1e-12:
                failures.append(f"t = {sample['t'][k]:.3f} s: the generic IK's step differs from the generated one's by {error:.1e}")
        q = closed(robot.integrate(q, v * DT), f"at t = {sample['t'][k]:.3f} s")
    seconds = time.perf_counter() - start

    foot_error = np.max(np.linalg.norm(log["feet"] - sample["foot"], axis=2))
    com_error = np.max(np.linalg.norm(log["com"] - log["com_ref"], axis=1))
    print(f"walked {args.steps} steps ({pattern.duration:.2f} s, {n} IK steps at 1 kHz) in {seconds:.2f} s of Python "
          f"({1e6 * seconds / n:.0f} us per tick: targets, IK step, kinematics for the log, integrate, Newton)")
    print(f"feet off the pattern at most {1e3 * foot_error:.3f} mm, CoM {1e3 * com_error:.3f} mm; legs at least "
          f"{1e3 * np.min(log['leg_distance']):.1f} mm apart (below the hips {1e3 * np.min(log['lower_leg_distance']):.1f} mm); |J v - xd| at most {np.max(log['null_space']):.1e} |J| |v|; "
          f"peak vertical angular momentum {np.max(np.abs(log['momentum'])):.3f} kg m^2/s")
    if args.check:
        if np.max(log["null_space"]) > 1e-12:
            failures.append(f"the step's velocity missed the task velocity by {np.max(log['null_space']):.1e} |J| |v|")
        if foot_error > 1e-3:
            failures.append(f"a foot left the pattern by {1e3 * foot_error:.2f} mm (> 1 mm)")
        if com_error > 5e-3:
            failures.append(f"the CoM left its reference by {1e3 * com_error:.2f} mm (> 5 mm)")
        if np.min(log["leg_distance"]) < 0.01:
            failures.append(f"the legs came within {1e3 * np.min(log['leg_distance']):.1f} mm (< 10 mm)")
        for failure in failures:
            print("FAILED:", failure)
        if failures:
            return 1

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        t = sample["t"]
        figure, (top, middle, bottom) = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
        top.plot(t, sample["zmp"][:, 1], "k:", label="ZMP reference (pattern)")
        top.plot(t, log["com_ref"][:, 1], "C0--", label="CoM reference")
        top.plot(t, log["com"][:, 1], "C0", label="CoM")
        top.plot(t, log["feet"][:, 0, 1], "C2", label="left foot")
        top.plot(t, log["feet"][:, 1, 1], "C3", label="right foot")
        top.set_ylabel("lateral position y [m]")
        top.set_ylim(-0.11, 0.17)  # room for the legend above the feet
        top.legend(loc="upper right", fontsize=8, ncol=2)
        top.set_title(f"Lola walks {args.steps} steps from Python (generated IK, avoidance + momentum)")
        middle.plot(t, log["feet"][:, 0, 2], "C2", label="left foot height")
        middle.plot(t, log["feet"][:, 1, 2], "C3", label="right foot height")
        middle.set_ylabel("height z [m]")
        middle.legend(loc="upper right", fontsize=8)
        bottom.plot(t, 1e3 * log["lower_leg_distance"], "C4", label="closest pair between the legs below the hips (exact below 50 mm)")
        bottom.plot(t, 1e3 * log["leg_distance"], "C5", label="closest pair between the legs (the hips' links)")
        bottom.axhline(50, color="C4", ls=":", label="avoidance's activation distance")
        bottom.set_ylabel("distance [mm]")
        bottom.set_ylim(0, 80)  # room for the legend above the activation distance
        bottom.set_xlabel("time [s]")
        bottom.legend(loc="upper right", fontsize=8)
        figure.tight_layout()
        figure.savefig(args.plot, dpi=100)
        print(f"wrote {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
