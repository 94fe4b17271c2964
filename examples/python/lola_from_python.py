#!/usr/bin/env python3
"""Lola from Python: the generated module against the generic runtime, what a call costs, and a
short drop onto the ground on both backends, plotted (docs/python.md).

    PYTHONPATH=build/examples:build/python python3 examples/python/lola_from_python.py [--plot FILE.png]

`lola` is the demo robot's generated module (examples/CMakeLists.txt: mbgen_add_robot(... PYTHON),
built with the project's flags); `mbgen` the package of python/ (load, the generic runtime, the
simulator). ctest's example.python_lola runs this script."""
import argparse
import os
import time

import numpy as np

import lola
import mbgen

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def per_call(function, repeats):
    """Seconds per call: the best of five runs of `repeats` calls."""
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(repeats):
            function()
        best = min(best, (time.perf_counter() - start) / repeats)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the drop's chart to this PNG (needs matplotlib)")
    parser.add_argument("--duration", type=float, default=1.0, help="seconds of the drop (default 1)")
    parser.add_argument("--bandwidth", type=float, default=40.0, help="the PD's natural frequency per joint, Hz (default 40)")
    args = parser.parse_args()

    robot = mbgen.load(os.path.join(ROOT, "robots/lola/lola.urdf"), extras=os.path.join(ROOT, "robots/lola/lola.yaml"),
                       base="floating")
    print(f"robot {robot.name}: nq {robot.nq}, nv {robot.nv}, ny {robot.ny} independent coordinates, "
          f"{'with' if robot.has_loops else 'without'} loops; generated module {lola.__name__}: "
          f"{sum(1 for name in dir(lola) if callable(getattr(lola, name)))} functions")

    # One state: the assembled pose, moved a little, closed again by the generated Newton.
    rng = np.random.default_rng(1)
    q, result = lola.closure_positions(robot.assembled_q)
    vy = rng.uniform(-1, 1, lola.ny)
    tau = rng.uniform(-10, 10, lola.nv)
    generated, generic = lola.forward_dynamics(q, vy, tau), robot.forward_dynamics(q, vy, tau)
    print(f"forward dynamics: generated vs generic {np.max(np.abs(generated - generic)) / np.max(np.abs(generic)):.1e} "
          f"(relative); closure {result.status.name} in {result.iterations} iterations")

    # What a call costs from Python: the generated function alone, one state per call and a
    # batch of 1000 in one call (the loop in C++), and the generic runtime.
    Q, V = np.tile(q, (1000, 1)), np.tile(vy, (1000, 1))
    single = per_call(lambda: lola.forward_dynamics(q, vy, tau), 2000)
    batched = per_call(lambda: lola.forward_dynamics(Q, V, tau), 5) / 1000
    generic_call = per_call(lambda: robot.forward_dynamics(q, vy, tau), 200)
    print(f"forward dynamics per state from Python: generated {single * 1e6:.2f} us per call, "
          f"{batched * 1e6:.2f} us in a batch of 1000 (so {max(single - batched, 0) * 1e6:.2f} us is the call), "
          f"generic {generic_call * 1e6:.2f} us ({generic_call / batched:.1f}x the batched generated)")

    # A drop: the lowest contact sphere 5 cm above the ground, the scene's compliant ground and end
    # stops, RK4, a PD controller written in Python; on the generated backend (lola.Simulator) and
    # on the generic one (mbgen.Simulator).
    # The controller, from the generated functions: PD with gravity compensation on the
    # independent joints towards the assembled pose, every millisecond, as mbgen_sim's
    # (runtime/include/mbgen/sim/pd_gravity.hpp): tau_y = Kp (q_ref - q) - Kd vy + T^T g(q), the
    # gains from each joint's effective inertia at the bandwidth.
    joints = np.array([i for i, vi in enumerate(lola.independent_v_index) if vi >= 6])  # the base is not driven
    columns = np.asarray(lola.independent_v_index)[joints]
    T = lola.velocity_map(q)
    inertia = 1 / np.diag(np.linalg.inv(T.T @ lola.mass_matrix(q) @ T))[joints]
    w = 2 * np.pi * args.bandwidth
    kp, kd = w * w * inertia, 2 * w * inertia
    reference = q[columns + 1]  # a floating base: a joint's q index is its v index + 1
    zeros = np.zeros(lola.nv)

    def hold_pose(t, q_now, v_now):
        gravity = lola.velocity_map(q_now).T @ lola.inverse_dynamics(q_now, zeros, zeros)
        tau = np.zeros(lola.nv)
        tau[columns] = kp * (reference - q_now[columns + 1]) - kd * v_now[columns] + gravity[joints]
        return tau

    start = q.copy()
    centres, _ = lola.contact_points(start)
    start[2] += lola.ground_offset + 0.05 - np.min(centres[:, 2] - lola.contact_sphere_radius)
    weight = 9.81 * np.linalg.norm(robot.centroidal_momentum_matrix(start)[:3, 0])
    drops = {}
    for name, simulator in (("generated", lola.Simulator(integrator="rk4", step=1e-4)),
                            ("generic", mbgen.Simulator(robot, integrator="rk4", step=1e-4))):
        simulator.set_controller(hold_pose)
        simulator.set_state(start, np.zeros(robot.nv))
        times, height, normal = [], [], []
        status = "ok"
        began = time.perf_counter()
        for k in range(1, int(round(args.duration / 1e-3)) + 1):
            status = simulator.run_until(k * 1e-3)
            if status != "ok":
                break
            times.append(simulator.time)
            height.append(simulator.q[2])
            normal.append(float(np.sum(simulator.contacts()["force"][:, 2])))
        cpu = time.perf_counter() - began
        drops[name] = (times, height, normal, status)
        print(f"drop ({name} backend): {simulator.time:.3f} s simulated in {cpu:.2f} s of CPU, status {status}; "
              f"pelvis from {height[0]:.3f} m to {height[-1]:.3f} m; ground force at the end {normal[-1]:.0f} N "
              f"(weight {weight:.0f} N)")
    gap = max(abs(a - b) for a, b in zip(drops["generated"][1], drops["generic"][1]))
    print(f"the two backends' pelvis heights differ by {gap:.1e} m at most")
    times, height, normal, status = drops["generated"]

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        top.plot(times, height)
        top.set_ylabel("pelvis height (m)")
        top.set_title("Lola dropped 5 cm, PD + gravity in Python (lola.Simulator, RK4 0.1 ms)")
        peak = max(normal)
        bottom.plot(times, normal, label=f"ground's normal force (impact peak {peak / 1e3:.1f} kN, off the scale)")
        bottom.set_ylim(0, 5 * weight)
        bottom.axhline(weight, color="gray", linestyle="--", label="weight")
        bottom.set_ylabel("force (N)")
        bottom.set_xlabel("time (s)")
        bottom.legend(loc="upper right")
        figure.tight_layout()
        figure.savefig(args.plot, dpi=100)
        print(f"chart: {args.plot}")
    return 0 if all(drop[3] == "ok" for drop in drops.values()) else 1


if __name__ == "__main__":
    raise SystemExit(main())
