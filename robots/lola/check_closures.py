#!/usr/bin/env python3
"""Checks that the loop closures of mbgen robot descriptions close, in pure Python.

    python3 robots/lola/check_closures.py                      # every robot shipped in robots/
    python3 robots/lola/check_closures.py A.urdf A.yaml ...    # given URDF + extras pairs

For each description it
  1. parses the URDF (xml.etree) and the closures of the YAML extras (mbgen schema);
  2. checks every inertial (mass > 0, inertia positive definite, triangle inequality);
  3. computes the forward kinematics of both frames of every closure at the nominal pose
     (all joint values 0) and prints the position residual and the rotation residual
     |R_parent^T R_child - I|_F (for revolute closures also the misalignment of the axes);
  4. for the shipped robots, moves the input joints away from the nominal pose, re-closes the
     loops by Levenberg-Marquardt on the tree joints of the loops, and compares the result with
     the closed forms written in the READMEs (Freudenstein, slider-crank, actuator lengths).
     The closed forms take their geometry from the URDF/YAML, not from the generator scripts.
Exit status 1 if a nominal residual exceeds 1e-9 or a closed form disagrees by more than 1e-8.
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

try:
    import yaml
except ImportError:  # pragma: no cover
    sys.exit("check_closures.py needs PyYAML (python3-yaml)")

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
TOL_NOMINAL, TOL_CLOSED_FORM = 1e-9, 1e-8


# ------------------------------------------------------------------ small 3-D algebra
def mat_mul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(A, v):
    return [sum(A[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def axis_angle(axis, a):
    n = math.sqrt(sum(x * x for x in axis))
    x, y, z = (c / n for c in axis)
    c, s, C = math.cos(a), math.sin(a), 1 - math.cos(a)
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def compose(T1, T2):  # (R, p)
    return (mat_mul(T1[0], T2[0]), [a + b for a, b in zip(mat_vec(T1[0], T2[1]), T1[1])])


def eig_sym3(A):
    """Eigenvalues of a symmetric 3x3 (closed form)."""
    p1 = A[0][1] ** 2 + A[0][2] ** 2 + A[1][2] ** 2
    q = (A[0][0] + A[1][1] + A[2][2]) / 3
    if p1 == 0:
        return sorted([A[0][0], A[1][1], A[2][2]])
    p2 = sum((A[i][i] - q) ** 2 for i in range(3)) + 2 * p1
    p = math.sqrt(p2 / 6)
    B = [[(A[i][j] - (q if i == j else 0)) / p for j in range(3)] for i in range(3)]
    detB = (B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) - B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0])
            + B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0]))
    r = max(-1.0, min(1.0, detB / 2))
    phi = math.acos(r) / 3
    e1 = q + 2 * p * math.cos(phi)
    e3 = q + 2 * p * math.cos(phi + 2 * math.pi / 3)
    return sorted([e1, 3 * q - e1 - e3, e3])


# ------------------------------------------------------------------ description
class Description:
    def __init__(self, urdf_path, yaml_path):
        self.urdf_path, self.yaml_path = urdf_path, yaml_path
        root = ET.parse(urdf_path).getroot()
        self.links, self.joints, self.parent_joint = {}, {}, {}
        for l in root.findall("link"):
            inert = l.find("inertial")
            data = None
            if inert is not None:
                o = inert.find("origin")
                com = [float(x) for x in o.get("xyz", "0 0 0").split()] if o is not None else [0, 0, 0]
                I = inert.find("inertia")
                g = lambda k: float(I.get(k, "0"))
                data = (float(inert.find("mass").get("value")), com,
                        [[g("ixx"), g("ixy"), g("ixz")], [g("ixy"), g("iyy"), g("iyz")], [g("ixz"), g("iyz"), g("izz")]])
            self.links[l.get("name")] = data
        for j in root.findall("joint"):
            o = j.find("origin")
            xyz = [float(x) for x in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
            rpy = [float(x) for x in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
            ax = j.find("axis")
            axis = [float(x) for x in ax.get("xyz").split()] if ax is not None else [1, 0, 0]
            lim = j.find("limit")
            rng = (float(lim.get("lower", "nan")), float(lim.get("upper", "nan"))) if lim is not None else None
            child = j.find("child").get("link")
            if child in self.parent_joint:
                raise SystemExit(f"{urdf_path}: link {child} has two parent joints")
            self.joints[j.get("name")] = dict(type=j.get("type"), parent=j.find("parent").get("link"), child=child,
                                              origin=(rpy_matrix(*rpy), xyz), axis=axis, range=rng)
            self.parent_joint[child] = j.get("name")
        with open(yaml_path) as f:
            self.extras = yaml.safe_load(f) or {}
        self.closures = self.extras.get("closures", []) or []
        self.moving = [n for n, j in self.joints.items() if j["type"] in ("revolute", "prismatic", "continuous")]

    def frame_link(self, name):
        """A frame name is a link, or a joint standing for its child link."""
        if name in self.links:
            return name
        return self.joints[name]["child"]

    def link_pose(self, link, q, cache=None):
        if cache is not None and link in cache:
            return cache[link]
        jn = self.parent_joint.get(link)
        if jn is None:
            T = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0])
        else:
            j = self.joints[jn]
            T = compose(self.link_pose(j["parent"], q, cache), j["origin"])
            v = q.get(jn, 0.0)
            if j["type"] in ("revolute", "continuous"):
                T = (mat_mul(T[0], axis_angle(j["axis"], v)), T[1])
            elif j["type"] == "prismatic":
                n = norm(j["axis"])
                T = (T[0], [a + b for a, b in zip(T[1], mat_vec(T[0], [v * c / n for c in j["axis"]]))])
        if cache is not None:
            cache[link] = T
        return T

    def closure_frames(self, c, q, cache=None):
        out = []
        for side in ("parent", "child"):
            o = c.get(side + "_origin", {}) or {}
            X = (rpy_matrix(*(o.get("rpy") or [0, 0, 0])), list(o.get("xyz") or [0, 0, 0]))
            out.append(compose(self.link_pose(self.frame_link(c[side]), q, cache), X))
        return out

    def residual(self, c, q, cache=None):
        """Constraint rows of one closure (position; plus axis alignment or full rotation)."""
        (R1, p1), (R2, p2) = self.closure_frames(c, q, cache)
        rows = [a - b for a, b in zip(p1, p2)]
        t = c.get("type", "weld")
        if t in ("revolute", "prismatic", "universal"):
            ax = c.get("axis") or [0, 0, 1]
            rows += cross(mat_vec(R1, ax), mat_vec(R2, ax)) if t != "universal" else []
        elif t == "weld" or t == "6d":
            E = mat_mul(transpose(R1), R2)
            rows += [E[2][1] - E[1][2], E[0][2] - E[2][0], E[1][0] - E[0][1]]
        return rows

    def path_joints(self, c):
        """Moving joints on the tree path between the two closure bodies."""
        def chain(link):
            js = []
            while link in self.parent_joint:
                js.append(self.parent_joint[link])
                link = self.joints[js[-1]]["parent"]
            return js
        a, b = chain(self.frame_link(c["parent"])), chain(self.frame_link(c["child"]))
        common = set(a) & set(b)
        return [j for j in a + b if j not in common and j in self.moving]


def check_inertias(d):
    bad, total = [], 0.0
    for name, data in d.links.items():
        if data is None:
            continue
        m, _, I = data
        total += m
        ev = eig_sym3(I)
        if m <= 0 or ev[0] <= 0:
            bad.append(f"{name}: mass {m}, eigenvalues {ev}")
        elif ev[0] + ev[1] < ev[2] * (1 - 1e-12):
            bad.append(f"{name}: triangle inequality {ev}")
    return total, bad


def solve(d, q, inputs, closures, iters=100):
    """Levenberg-Marquardt on the loop joints that are not inputs; returns (q, |residual|)."""
    unknown = sorted({j for c in closures for j in d.path_joints(c)} - set(inputs))
    q = dict(q)
    q.update(inputs)
    for j in unknown:
        q.setdefault(j, 0.0)

    def F(qq):
        cache = {}
        return [r for c in closures for r in d.residual(c, qq, cache)]

    lam = 1e-6
    f = F(q)
    for _ in range(iters):
        n2 = sum(x * x for x in f)
        if math.sqrt(n2) < 1e-14:
            break
        h = 1e-7
        J = []
        for j in unknown:
            qq = dict(q)
            qq[j] += h
            qm = dict(q)
            qm[j] -= h
            J.append([(a - b) / (2 * h) for a, b in zip(F(qq), F(qm))])   # columns
        n = len(unknown)
        A = [[sum(J[i][k] * J[j][k] for k in range(len(f))) + (lam if i == j else 0) for j in range(n)] for i in range(n)]
        g = [-sum(J[i][k] * f[k] for k in range(len(f))) for i in range(n)]
        dx = gauss(A, g)
        trial = dict(q)
        for j, v in zip(unknown, dx):
            trial[j] += v
        ft = F(trial)
        if sum(x * x for x in ft) < n2:
            q, f, lam = trial, ft, max(lam / 10, 1e-12)
        else:
            lam *= 10
    return q, math.sqrt(sum(x * x for x in f))


def gauss(A, b):
    n = len(b)
    M = [row[:] + [b[i]] for i, row in enumerate(A)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(M[r][c]))
        M[c], M[p] = M[p], M[c]
        for r in range(c + 1, n):
            f = M[r][c] / M[c][c]
            for k in range(c, n + 1):
                M[r][k] -= f * M[c][k]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (M[r][n] - sum(M[r][k] * x[k] for k in range(r + 1, n))) / M[r][r]
    return x


# ------------------------------------------------------------------ closed forms (README formulas)
def origin_xyz(d, joint):
    return d.joints[joint]["origin"][1]


def closure(d, name):
    return next(c for c in d.closures if c["name"] == name)


def cf_four_bar(d):
    """Freudenstein: K1 cos t4 - K2 cos t2 + K3 = cos(t2 - t4), t = t0 + q, angles in the x-z plane."""
    O2, O4 = origin_xyz(d, "crank_joint"), origin_xyz(d, "rocker_joint")
    B = origin_xyz(d, "coupler_joint")
    C = closure(d, "coupler_rocker")["child_origin"]["xyz"]
    Cc = closure(d, "coupler_rocker")["parent_origin"]["xyz"]
    a, b = math.hypot(*B[::2]), math.hypot(O4[0] - O2[0], O4[2] - O2[2])
    crank, ground, coupler, rocker = a, b, math.hypot(Cc[0], Cc[2]), math.hypot(C[0], C[2])
    t2_0, t4_0 = math.atan2(B[2], B[0]), math.atan2(C[2], C[0])
    K1, K2 = ground / crank, ground / rocker
    K3 = (crank ** 2 - coupler ** 2 + rocker ** 2 + ground ** 2) / (2 * crank * rocker)
    out = []
    for qc in (0.3, 1.0, 2.0, 3.0, -1.5):
        t2 = t2_0 + qc
        A_ = math.cos(t2) - K1 - K2 * math.cos(t2) + K3
        B_ = -2 * math.sin(t2)
        C_ = K1 - (K2 + 1) * math.cos(t2) + K3
        disc = math.sqrt(B_ * B_ - 4 * A_ * C_)
        sols = [2 * math.atan2(-B_ + sgn * disc, 2 * A_) for sgn in (-1, 1)]
        # the branch of the nominal pose
        t4 = min(sols, key=lambda t: abs(math.remainder(t - t4_0 - 0, 2 * math.pi)) if qc == 0 else 0)
        out.append(({"crank_joint": qc}, {"rocker_joint": [math.remainder(s - t4_0, 2 * math.pi) for s in sols]}))
    return out, ["coupler_rocker"]


def cf_slider_crank(d):
    """x = r cos t + sqrt(l^2 - (r sin t - e)^2), t = t0 + q_crank, slider q = x - x0."""
    B = origin_xyz(d, "rod_joint")
    r, t0 = math.hypot(B[0], B[2]), math.atan2(B[2], B[0])
    l = norm(closure(d, "rod_slider")["parent_origin"]["xyz"])
    S = origin_xyz(d, "slider_joint")
    e, x0 = S[2], S[0]
    out = []
    for qc in (0.5, 1.5, 3.0, -2.0):
        t = t0 + qc
        x = r * math.cos(t) + math.sqrt(l * l - (r * math.sin(t) - e) ** 2)
        out.append(({"crank_joint": qc}, {"slider_joint": [x - x0]}))
    return out, ["rod_slider"]


def ankle_cases(d, sfx, prefix, lat_sign):
    """Actuator extension = |A_i - (O + R_y(pitch) R_x(roll) b_i)| - L_i0 for both actuators."""
    out = []
    cl = [closure(d, f"ankle_{t}{sfx}") for t in ("lat", "med")]
    O = d.link_pose(d.frame_link(f"ankle_pitch{sfx}"), {})[1]
    shank = d.link_pose(d.joints[f"ankle_pitch{sfx}"]["parent"], {})[1]
    for pitch, roll in ((0.3, 0.0), (-0.4, 0.2), (0.6, -0.3), (0.1, 0.35)):
        R = mat_mul(axis_angle([0, 1, 0], pitch), axis_angle([1, 0, 0], roll))
        exp = {}
        for t, c in zip(("lat", "med"), cl):
            A = d.link_pose(d.frame_link(f"ankle_act_{t}_cross{sfx}"), {})[1]
            b = c["child_origin"]["xyz"]
            Bp = [o + v for o, v in zip(O, mat_vec(R, b))]
            L0 = norm([o + v - a for o, v, a in zip(O, b, A)])
            exp[f"ankle_act_{t}{sfx}"] = [norm([x - a for x, a in zip(Bp, A)]) - L0]
        out.append(({f"ankle_pitch{sfx}": pitch, f"ankle_roll{sfx}": roll}, exp))
    return out, [c["name"] for c in cl]


def knee_cases(d, sfx):
    """Slider-crank in the thigh: z_nut = P_z + sqrt(l^2 - (x_rail - P_x)^2), P = K + R_y(theta) c."""
    c = closure(d, f"knee_loop{sfx}")
    K = origin_xyz(d, f"knee{sfx}")
    crank = origin_xyz(d, f"knee_crank_fixed{sfx}")
    N0 = origin_xyz(d, f"knee_act{sfx}")
    l = norm(c["parent_origin"]["xyz"])
    out = []
    for th in (0.3, 1.0, 1.6, 2.0):
        P = [k + v for k, v in zip(K, mat_vec(axis_angle([0, 1, 0], th), crank))]
        z = P[2] + math.sqrt(l * l - (N0[0] - P[0]) ** 2)
        out.append(({f"knee{sfx}": th}, {f"knee_act{sfx}": [z - N0[2]]}))
    return out, [c["name"]]


def cf_ankle_2dof(d):
    return ankle_cases(d, "", "", 1)


def cf_lola(d):
    cases = []
    for sfx in ("_l", "_r"):
        cases.append(knee_cases(d, sfx))
        cases.append(ankle_cases(d, sfx, "", 1))
    return cases


CLOSED_FORMS = {"four_bar": cf_four_bar, "slider_crank": cf_slider_crank, "ankle_2dof": cf_ankle_2dof,
                "lola": cf_lola}


# ------------------------------------------------------------------ main
def check(urdf, yml):
    d = Description(urdf, yml)
    ok = True
    total, bad = check_inertias(d)
    name = os.path.splitext(os.path.basename(urdf))[0]
    nprism = sum(1 for j in d.moving if d.joints[j]["type"] == "prismatic")
    print(f"== {os.path.relpath(urdf, ROOT)} + {os.path.basename(yml)}")
    print(f"   links {len(d.links)}, moving joints {len(d.moving)} ({nprism} prismatic), "
          f"closures {len(d.closures)}, mass {total:.3f} kg, inertia problems: {len(bad)}")
    for b in bad:
        print("   BAD INERTIA", b)
        ok = False
    print("   nominal pose (all joints 0):")
    for c in d.closures:
        (R1, p1), (R2, p2) = d.closure_frames(c, {})
        dp = norm([a - b for a, b in zip(p1, p2)])
        E = mat_mul(transpose(R1), R2)
        dr = math.sqrt(sum((E[i][j] - (i == j)) ** 2 for i in range(3) for j in range(3)))
        extra = ""
        if c.get("type") == "revolute":
            ax = c.get("axis") or [0, 0, 1]
            extra = f", axis misalignment {norm(cross(mat_vec(R1, ax), mat_vec(R2, ax))):.1e}"
        flag = "ok" if dp <= TOL_NOMINAL and dr <= TOL_NOMINAL else "OPEN"
        ok &= flag == "ok"
        print(f"   {c['name']:<16} {c.get('type'):<10} position residual {dp:.1e} m, rotation residual {dr:.1e}{extra}  {flag}")
    if name in CLOSED_FORMS:
        res = CLOSED_FORMS[name](d)
        groups = res if isinstance(res, list) else [res]
        worst = 0.0
        print("   away from the nominal pose (loops re-closed numerically vs the closed form):")
        for cases, cnames in groups:
            cls = [closure(d, n) for n in cnames]
            q, prev = {}, {}
            for inputs, expected in cases:
                # continuation in 20 steps from the previous inputs, so the solve stays on the
                # assembly branch of the nominal pose
                for k in range(1, 21):
                    step = {j: prev.get(j, 0.0) + (v - prev.get(j, 0.0)) * k / 20 for j, v in inputs.items()}
                    q, r = solve(d, q, step, cls)
                prev = dict(inputs)
                for j, vals in expected.items():
                    err = min(abs(q[j] - v) for v in vals)
                    worst = max(worst, err)
                    print(f"   {', '.join(f'{k}={v:+.3f}' for k, v in inputs.items()):<38} -> {j} = {q[j]:+.9f} "
                          f"(closed form {min(vals, key=lambda v: abs(q[j] - v)):+.9f}, |diff| {err:.1e}, "
                          f"loop residual {r:.1e})")
        if worst > TOL_CLOSED_FORM:
            ok = False
            print(f"   CLOSED FORM MISMATCH {worst:.2e}")
    return ok


def main(argv):
    pairs = list(zip(argv[0::2], argv[1::2])) if argv else [
        (os.path.join(ROOT, "lola", "lola.urdf"), os.path.join(ROOT, "lola", "lola.yaml"))] + [
        (os.path.join(ROOT, "mechanisms", n + ".urdf"), os.path.join(ROOT, "mechanisms", n + ".yaml"))
        for n in ("four_bar", "slider_crank", "ankle_2dof")
        if os.path.exists(os.path.join(ROOT, "mechanisms", n + ".urdf"))]
    ok = all([check(u, y) for u, y in pairs])
    print("ALL CLOSED" if ok else "FAILURES")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
