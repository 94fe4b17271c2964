"""Small helpers that write URDF trees with inertias computed from solid primitives.

Used by robots/lola/make_lola.py and robots/mechanisms/make_mechanisms.py. Every inertia is the
exact inertia of a homogeneous solid (box, cylinder, sphere) of the given mass about its centre,
optionally rotated into the link frame, so it is positive definite and satisfies the triangle
inequality by construction. Pure Python (no numpy needed).
"""
import math


def _fmt(v):
    """Shortest round-trip representation of a float; -0.0 printed as 0."""
    v = round(float(v), 12)      # drop float noise such as -0.11999999999999997
    if v == 0:
        return "0"
    return repr(v)


def vec(v):
    return " ".join(_fmt(x) for x in v)


# ---------------------------------------------------------------- inertia of solids about their centre
def box_inertia(m, sx, sy, sz):
    return [[m * (sy * sy + sz * sz) / 12, 0, 0],
            [0, m * (sx * sx + sz * sz) / 12, 0],
            [0, 0, m * (sx * sx + sy * sy) / 12]]


def cylinder_inertia(m, r, h, axis="z"):
    a = m * r * r / 2                       # about the cylinder axis
    p = m * (3 * r * r + h * h) / 12        # about a diameter through the centre
    d = {"x": [a, p, p], "y": [p, a, p], "z": [p, p, a]}[axis]
    return [[d[0], 0, 0], [0, d[1], 0], [0, 0, d[2]]]


def sphere_inertia(m, r):
    i = 2 * m * r * r / 5
    return [[i, 0, 0], [0, i, 0], [0, 0, i]]


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rotate_inertia(R, I):
    """R I R^T."""
    RI = [[sum(R[i][k] * I[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return [[sum(RI[i][k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]


def rod_inertia_xz(m, r, p0, p1):
    """Solid cylinder of radius r from p0 to p1 (both in the x-z plane, y equal): inertia about
    its centre in the link frame (the cylinder axis is rotated from z into the direction p1-p0)."""
    dx, dz = p1[0] - p0[0], p1[2] - p0[2]
    h = math.hypot(dx, dz)
    ang = math.atan2(dx, dz)                # rotation about y taking +z to (dx, 0, dz)/h
    return rotate_inertia(rot_y(ang), cylinder_inertia(m, r, h, "z")), h


# ---------------------------------------------------------------- URDF writer
class Urdf:
    def __init__(self, name, header=""):
        self.name = name
        self.header = header
        self.parts = []
        self.mass = {}

    def link(self, name, mass=None, com=(0, 0, 0), inertia=None, collisions=(), comment=None):
        """collisions: list of ('sphere', r, xyz) | ('cylinder', r, length, xyz, rpy) | ('box', size, xyz)."""
        out = []
        if comment:
            out.append(f"  <!-- {comment} -->")
        out.append(f'  <link name="{name}">')
        if mass is not None:
            I = inertia
            out.append("    <inertial>")
            out.append(f'      <origin xyz="{vec(com)}" rpy="0 0 0"/>')
            out.append(f'      <mass value="{_fmt(mass)}"/>')
            out.append('      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>' % tuple(
                _fmt(round(x, 12)) for x in (I[0][0], I[0][1], I[0][2], I[1][1], I[1][2], I[2][2])))
            out.append("    </inertial>")
            self.mass[name] = mass
        for c in collisions:
            kind = c[0]
            if kind == "sphere":
                _, r, xyz = c
                geom, origin = f'<sphere radius="{_fmt(r)}"/>', f'<origin xyz="{vec(xyz)}" rpy="0 0 0"/>'
            elif kind == "cylinder":
                _, r, length, xyz, rpy = c
                geom, origin = (f'<cylinder radius="{_fmt(r)}" length="{_fmt(length)}"/>',
                                f'<origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>')
            elif kind == "box":
                _, size, xyz = c
                geom, origin = f'<box size="{vec(size)}"/>', f'<origin xyz="{vec(xyz)}" rpy="0 0 0"/>'
            else:
                raise ValueError(kind)
            out.append("    <collision>")
            out.append(f"      {origin}")
            out.append(f"      <geometry>{geom}</geometry>")
            out.append("    </collision>")
        out.append("  </link>")
        self.parts.append("\n".join(out))

    def joint(self, name, jtype, parent, child, xyz=(0, 0, 0), rpy=(0, 0, 0), axis=None,
              lower=None, upper=None, effort=None, velocity=None, comment=None):
        out = []
        if comment:
            out.append(f"  <!-- {comment} -->")
        out.append(f'  <joint name="{name}" type="{jtype}">')
        out.append(f'    <parent link="{parent}"/>')
        out.append(f'    <child link="{child}"/>')
        out.append(f'    <origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>')
        if jtype in ("revolute", "prismatic", "continuous"):
            out.append(f'    <axis xyz="{vec(axis)}"/>')
            if jtype != "continuous":
                out.append(f'    <limit lower="{_fmt(lower)}" upper="{_fmt(upper)}" '
                           f'effort="{_fmt(effort)}" velocity="{_fmt(velocity)}"/>')
        out.append("  </joint>")
        self.parts.append("\n".join(out))

    def text(self):
        head = '<?xml version="1.0"?>\n'
        if self.header:
            head += "<!--\n" + self.header.rstrip() + "\n-->\n"
        return head + f'<robot name="{self.name}">\n' + "\n".join(self.parts) + "\n</robot>\n"

    def write(self, path):
        with open(path, "w") as f:
            f.write(self.text())
