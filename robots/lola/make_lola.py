#!/usr/bin/env python3
"""Writes lola.urdf, lola.yaml, lola_legs.yaml and lola_legs_transmission.yaml (run from anywhere: python3 robots/lola/make_lola.py).

A biped modelled after the TUM robot Lola. Every number below is either a published figure
(see README.md, "Sources") or derived by a stated rule; this script is the single place where
the geometry lives, so the URDF, the YAML closures and the README tables cannot drift apart.
Conventions: x forward, y left, z up; every link frame is parallel to the pelvis frame at the
nominal pose (all joint values 0: straight legs, arms hanging, feet flat).
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
from urdfkit import (Urdf, box_inertia, cylinder_inertia, sphere_inertia, vec)  # noqa: E402

# ------------------------------------------------------------------ dimensions (metres)
H = 1.80                      # total height (published)
ANKLE_H = 0.08                # sole to ankle axis
SHANK = 0.44                  # knee axis to ankle axis   (~0.246 H, Drillis & Contini)
THIGH = 0.44                  # hip axis to knee axis     (~0.245 H)
HIP_ROLL_DROP = 0.08          # hip-yaw joint plane (pelvis frame) to hip roll/pitch axes
HIP_Y = 0.09                  # lateral offset of each hip from the mid-plane
HIP_ROLL_BLOCK_R = 0.082      # collision sphere of the hip-pitch drive block (encloses its r 0.055 x 0.12 cylinder)
PELVIS_Z = ANKLE_H + SHANK + THIGH + HIP_ROLL_DROP   # 1.04 m: pelvis frame above the ground
TRUNK_YAW_Z = 0.10            # pelvis frame to trunk-yaw joint
TRUNK_ROLL_Z = 0.06           # trunk-yaw joint to trunk-roll joint (torso frame)
SHOULDER = (0.0, 0.20, 0.27)  # in torso frame -> shoulder height 1.47 m (~0.818 H)
SHOULDER_ROLL_Y = 0.05
UPPER_ARM = 0.30              # shoulder to elbow (~0.186 H = 0.335, shortened: Lola's arms are short)
FOREARM = 0.27                # elbow to hand frame (~0.146 H + hand cap)
HEAD_PAN_Z = 0.40             # torso frame to head-pan joint (1.60 m)
HEAD_TILT_Z = 0.06            # head-pan joint to head-tilt joint (1.66 m); head top at 1.80 m
HEEL_X, TOE_JOINT_X, TOE_LEN = -0.07, 0.14, 0.07   # foot: heel, toe joint, toe tip = 0.21
FOOT_W = 0.12

# knee slider-crank (thigh frame: origin on the hip pitch axis; shank frame: origin on the knee axis)
KNEE_CRANK = (0.03, 0.0, 0.052)     # crank pin in the shank frame (|r| = 0.06 m, 60 deg above the +x axis)
KNEE_ROD = 0.18                     # connecting rod length, pin to pin
KNEE_RAIL_X = KNEE_CRANK[0]         # the nut slides along z at this x (rod vertical at the nominal pose)
KNEE_NUT0 = (KNEE_RAIL_X, 0.0, -THIGH + KNEE_CRANK[2] + KNEE_ROD)   # (0.03, 0, -0.208)

# ankle: two U-P-S actuators from the shank to the heel (shank frame)
ACT_X, ACT_Y = -0.05, 0.045         # heel attachment points b = (ACT_X, +-ACT_Y, 0) in the foot frame
ACT_TOP_Z = -0.10                   # universal joints of the actuator housings, below the knee axis
ACT_NUT_DROP = 0.22                 # housing top to the rod's frame (nut) at the nominal pose
ACT_ROD = SHANK + ACT_TOP_Z - ACT_NUT_DROP   # = 0.12: nut to the heel ball joint
assert abs(ACT_ROD - 0.12) < 1e-12

# ------------------------------------------------------------------ joint data
# name: (lower, upper, effort, velocity) for the left side; right side mirrors roll/yaw signs.
LIM = {
    "hip_yaw":        (-0.60, 0.60, 60.0, 6.0),
    "hip_roll":       (-0.35, 0.52, 150.0, 5.0),
    "hip_pitch":      (-1.90, 0.50, 200.0, 6.0),
    "knee":           (0.0, 2.0944, 0.0, 10.0),     # passive in the tree (driven through the loop)
    "ankle_pitch":    (-0.50, 0.70, 0.0, 10.0),     # passive
    "ankle_roll":     (-0.35, 0.35, 0.0, 10.0),     # passive
    "toe":            (-1.00, 0.10, 30.0, 6.0),
    "trunk_yaw":      (-0.80, 0.80, 60.0, 3.0),
    "trunk_roll":     (-0.30, 0.30, 100.0, 3.0),
    "shoulder_pitch": (-2.50, 1.00, 40.0, 5.0),
    "shoulder_roll":  (-0.10, 1.60, 40.0, 5.0),
    "elbow":          (-2.30, 0.0, 30.0, 5.0),
    "head_pan":       (-1.20, 1.20, 5.0, 5.0),
    "head_tilt":      (-0.50, 0.80, 5.0, 5.0),
}
MIRROR = {"hip_yaw", "hip_roll", "ankle_roll", "shoulder_roll"}   # limits mirror on the right side

# harmonic drives: joint -> (gear ratio, rotor inertia before the gear [kg m^2])
DRIVES = {
    "hip_yaw": (100, 3.0e-5), "hip_roll": (160, 4.0e-5), "hip_pitch": (100, 6.0e-5),
    "toe": (100, 1.0e-5),
    "trunk_yaw": (100, 3.0e-5), "trunk_roll": (100, 3.0e-5),
    "shoulder_pitch": (100, 2.0e-5), "shoulder_roll": (100, 2.0e-5), "elbow": (100, 1.5e-5),
    "head_pan": (50, 1.0e-5), "head_tilt": (50, 1.0e-5),
}


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def mv(R, v):
    return [sum(R[i][k] * v[k] for k in range(3)) for i in range(3)]


def mm(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


# ------------------------------------------------------------------ closed forms (used for limits, README)
def knee_nut(theta):
    """Slider-crank: nut position along the rail (thigh z) and rod angle for knee angle theta."""
    c = KNEE_CRANK
    px = c[0] * math.cos(theta) + c[2] * math.sin(theta)
    pz = -THIGH - c[0] * math.sin(theta) + c[2] * math.cos(theta)
    dx = KNEE_RAIL_X - px
    z = pz + math.sqrt(KNEE_ROD ** 2 - dx ** 2)
    rod = math.atan2(-(px - KNEE_RAIL_X), -(pz - z))   # R_y(rod) (0,0,-l) = P - N
    return z - KNEE_NUT0[2], rod


def ankle_lengths(pitch, roll):
    """U-P-S ankle: extension of each actuator (lateral, medial) from its nominal length,
    and its universal-joint angles, for foot pitch (about y) then roll (about x)."""
    R = mm(rot_y(pitch), rot_x(roll))
    out = []
    for sy in (+1, -1):
        a = (ACT_X, sy * ACT_Y, ACT_TOP_Z)
        b = mv(R, (ACT_X, sy * ACT_Y, 0.0))
        d = [b[0] - a[0], b[1] - a[1], b[2] - SHANK - a[2]]
        L = math.sqrt(sum(x * x for x in d))
        u = [x / L for x in d]
        u2 = math.asin(u[1])
        u1 = math.atan2(-u[0], -u[2])
        out.append((L - (ACT_NUT_DROP + ACT_ROD), u1, u2))
    return out


def ranges():
    th = [LIM["knee"][0] + i * (LIM["knee"][1] - LIM["knee"][0]) / 400 for i in range(401)]
    kn = [knee_nut(t) for t in th]
    ext, u1s, u2s = [], [], []
    P0, P1 = LIM["ankle_pitch"][:2]
    R0, R1 = LIM["ankle_roll"][:2]
    for i in range(41):
        for j in range(41):
            for e, u1, u2 in ankle_lengths(P0 + (P1 - P0) * i / 40, R0 + (R1 - R0) * j / 40):
                ext.append(e); u1s.append(u1); u2s.append(u2)
    return (min(k[0] for k in kn), max(k[0] for k in kn), min(k[1] for k in kn), max(k[1] for k in kn),
            min(ext), max(ext), min(u1s), max(u1s), min(u2s), max(u2s))


def pad(lo, hi, m):
    return (math.floor((lo - m) * 1000) / 1000, math.ceil((hi + m) * 1000) / 1000)


RANGES = ranges()
KNEE_ACT_LIM = pad(RANGES[0], RANGES[1], 0.005)
KNEE_ROD_LIM = pad(RANGES[2], RANGES[3], 0.05)
ANKLE_ACT_LIM = pad(RANGES[4], RANGES[5], 0.005)
ANKLE_U1_LIM = pad(RANGES[6], RANGES[7], 0.05)
ANKLE_U2_LIM = pad(RANGES[8], RANGES[9], 0.05)


# ------------------------------------------------------------------ building blocks
U = None
SSV = {}        # link -> list of (kind, points, radius)
COLL_EXTRA = {}


def capsule_collisions(p0, p1, r):
    """URDF has no capsule: a cylinder between the two points plus a sphere at each end."""
    d = [p1[i] - p0[i] for i in range(3)]
    L = math.sqrt(sum(x * x for x in d))
    mid = [(p0[i] + p1[i]) / 2 for i in range(3)]
    if L < 1e-12:
        return [("sphere", r, p0)]
    pitch = math.acos(max(-1.0, min(1.0, d[2] / L)))
    yaw = math.atan2(d[1], d[0]) if abs(d[0]) + abs(d[1]) > 1e-12 else 0.0
    rpy = (0.0, round(pitch, 15), round(yaw, 15))
    return [("cylinder", r, L, mid, rpy), ("sphere", r, p0), ("sphere", r, p1)]


def seg(link, p0, p1, r, ssv=True):
    """Declare a capsule (line-SSV) for a link: goes to <collision> and, if ssv, to the YAML."""
    COLL_EXTRA.setdefault(link, []).extend(capsule_collisions(p0, p1, r))
    if ssv:
        SSV.setdefault(link, []).append(("line", [p0, p1], r))


def ball(link, p, r, ssv=True):
    COLL_EXTRA.setdefault(link, []).append(("sphere", r, p))
    if ssv:
        SSV.setdefault(link, []).append(("point", [p], r))


def link(name, mass, com, inertia, note):
    LINKS.append((name, mass, com, inertia, note))


LINKS = []      # (name, mass, com, inertia, note)
JOINTS = []     # kwargs for Urdf.joint
MASS_TABLE = []  # (link, mass, primitive, rule)


def body(name, mass, com, prim, dims, rule):
    if prim == "box":
        I = box_inertia(mass, *dims)
        desc = "box %s" % " x ".join("%g" % d for d in dims)
    elif prim.startswith("cyl"):
        r, h, ax = dims
        I = cylinder_inertia(mass, r, h, ax)
        desc = "cylinder r %g, l %g along %s" % (r, h, ax)
    elif prim == "sphere":
        I = sphere_inertia(mass, dims[0])
        desc = "sphere r %g" % dims[0]
    LINKS.append((name, mass, com, I))
    MASS_TABLE.append((name, mass, com, desc, rule))


def joint(name, jtype, parent, child, xyz, axis=None, lim=None, comment=None):
    kw = dict(name=name, jtype=jtype, parent=parent, child=child, xyz=xyz, comment=comment)
    if jtype != "fixed":
        kw.update(axis=axis, lower=lim[0], upper=lim[1], effort=lim[2], velocity=lim[3])
    JOINTS.append(kw)


def lim_of(base, side):
    lo, hi, eff, vel = LIM[base]
    if side == "r" and base in MIRROR:
        lo, hi = -hi, -lo
    return (lo, hi, eff, vel)


# ------------------------------------------------------------------ the robot
def build():
    body("pelvis", 8.0, (0, 0, 0.02), "box", (0.20, 0.30, 0.14),
         "pelvis frame, hip-yaw drives, battery-free electronics (mass budget, see README)")
    seg("pelvis", (0, -0.09, 0.03), (0, 0.09, 0.03), 0.10)

    # ---- trunk: 2 DoF between pelvis and upper body (yaw, then roll)
    joint("trunk_yaw", "revolute", "pelvis", "trunk_link", (0, 0, TRUNK_YAW_Z), (0, 0, 1), LIM["trunk_yaw"])
    body("trunk_link", 1.2, (0, 0, 0.03), "cyl", (0.06, 0.06, "z"), "trunk-yaw output flange + roll drive")
    joint("trunk_roll", "revolute", "trunk_link", "torso", (0, 0, TRUNK_ROLL_Z), (1, 0, 0), LIM["trunk_roll"])
    body("torso", 17.0, (0, 0, 0.18), "box", (0.22, 0.32, 0.36), "upper body: computers, power electronics, IMU")
    seg("torso", (0, -0.06, 0.18), (0, 0.06, 0.18), 0.13)

    # ---- head: pan, tilt
    joint("head_pan", "revolute", "torso", "neck", (0, 0, HEAD_PAN_Z), (0, 0, 1), LIM["head_pan"])
    body("neck", 0.3, (0, 0, 0.025), "cyl", (0.03, 0.05, "z"), "pan drive output")
    joint("head_tilt", "revolute", "neck", "head", (0, 0, HEAD_TILT_Z), (0, 1, 0), LIM["head_tilt"])
    body("head", 1.5, (0.02, 0, 0.06), "box", (0.16, 0.20, 0.16), "stereo camera head")
    ball("head", (0.02, 0, 0.06), 0.11)

    for side, s in (("l", 1), ("r", -1)):
        arm(side, s)
        leg(side, s)


def arm(side, s):
    sh = (SHOULDER[0], s * SHOULDER[1], SHOULDER[2])
    joint(f"shoulder_pitch_{side}", "revolute", "torso", f"shoulder_{side}", sh, (0, 1, 0),
          lim_of("shoulder_pitch", side))
    body(f"shoulder_{side}", 0.5, (0, s * 0.025, 0), "cyl", (0.04, 0.06, "y"), "shoulder roll drive")
    joint(f"shoulder_roll_{side}", "revolute", f"shoulder_{side}", f"upper_arm_{side}",
          (0, s * SHOULDER_ROLL_Y, 0), (1, 0, 0), lim_of("shoulder_roll", side))
    body(f"upper_arm_{side}", 1.2, (0, 0, -0.15), "cyl", (0.04, 0.28, "z"), "upper arm with elbow drive")
    seg(f"upper_arm_{side}", (0, 0, -0.04), (0, 0, -0.26), 0.045)
    joint(f"elbow_{side}", "revolute", f"upper_arm_{side}", f"forearm_{side}", (0, 0, -UPPER_ARM), (0, 1, 0),
          lim_of("elbow", side))
    body(f"forearm_{side}", 0.9, (0, 0, -0.12), "cyl", (0.035, 0.24, "z"), "forearm")
    seg(f"forearm_{side}", (0, 0, -0.03), (0, 0, -0.22), 0.04)
    joint(f"hand_fixed_{side}", "fixed", f"forearm_{side}", f"hand_{side}", (0, 0, -FOREARM))
    body(f"hand_{side}", 0.2, (0, 0, 0), "sphere", (0.04,), "end cap (Lola has no hands)")
    ball(f"hand_{side}", (0, 0, 0), 0.05)


def leg(side, s):
    # ---- hip: yaw, roll, pitch (roll and pitch axes intersect)
    joint(f"hip_yaw_{side}", "revolute", "pelvis", f"hip_yaw_link_{side}", (0, s * HIP_Y, 0), (0, 0, 1),
          lim_of("hip_yaw", side))
    body(f"hip_yaw_link_{side}", 1.4, (0, 0, -0.04), "cyl", (0.05, 0.08, "z"), "hip-roll drive")
    ball(f"hip_yaw_link_{side}", (0, 0, -0.04), 0.06, ssv=False)
    joint(f"hip_roll_{side}", "revolute", f"hip_yaw_link_{side}", f"hip_roll_link_{side}",
          (0, 0, -HIP_ROLL_DROP), (1, 0, 0), lim_of("hip_roll", side))
    body(f"hip_roll_link_{side}", 1.8, (0, 0, 0), "cyl", (0.055, 0.12, "y"), "hip-pitch drive (cardan block)")
    # The drive block is the cylinder above (r 0.055, l 0.12 along y) centred on the hip, and the
    # hips are 2 x HIP_Y = 0.18 m apart: any capsule along y that encloses the cylinder reaches
    # past the mid-plane (r + half its segment >= 0.115 > 0.09), so the two would overlap at the
    # nominal pose. Its circumscribed sphere (r = sqrt(0.06^2 + 0.055^2) = 0.0814) encloses it
    # too and reaches 0.082 m: 16 mm between the left and right blocks.
    ball(f"hip_roll_link_{side}", (0, 0, 0), HIP_ROLL_BLOCK_R, ssv=False)
    joint(f"hip_pitch_{side}", "revolute", f"hip_roll_link_{side}", f"thigh_{side}", (0, 0, 0), (0, 1, 0),
          lim_of("hip_pitch", side))
    body(f"thigh_{side}", 2.0, (0, 0, -0.22), "box", (0.08, 0.08, 0.40), "thigh structure")
    seg(f"thigh_{side}", (0, 0, -0.06), (0, 0, -0.38), 0.065)
    # knee actuator: motor + roller screw fixed in the thigh (a frame with its own mass)
    joint(f"knee_motor_fixed_{side}", "fixed", f"thigh_{side}", f"knee_motor_{side}", (KNEE_RAIL_X, 0, -0.09))
    body(f"knee_motor_{side}", 1.0, (0, 0, 0), "cyl", (0.035, 0.10, "z"), "knee motor + screw, near the hip")
    # nut / slider on the screw (actuated prismatic), connecting rod
    joint(f"knee_act_{side}", "prismatic", f"thigh_{side}", f"knee_nut_{side}", KNEE_NUT0, (0, 0, 1),
          (KNEE_ACT_LIM[0], KNEE_ACT_LIM[1], 5000.0, 0.4),
          comment="knee linear actuator: nut on the roller screw, q = nut travel along the thigh (m)")
    body(f"knee_nut_{side}", 0.25, (0, 0, 0), "box", (0.04, 0.05, 0.04), "roller-screw nut and carriage")
    COLL_EXTRA.setdefault(f"knee_nut_{side}", []).append(("sphere", 0.03, (0, 0, 0)))
    joint(f"knee_rod_joint_{side}", "revolute", f"knee_nut_{side}", f"knee_rod_{side}", (0, 0, 0), (0, 1, 0),
          (KNEE_ROD_LIM[0], KNEE_ROD_LIM[1], 0.0, 20.0))
    body(f"knee_rod_{side}", 0.15, (0, 0, -KNEE_ROD / 2), "cyl", (0.008, KNEE_ROD, "z"), "connecting rod")
    seg(f"knee_rod_{side}", (0, 0, 0), (0, 0, -KNEE_ROD), 0.012, ssv=False)
    # knee (passive in the tree)
    joint(f"knee_{side}", "revolute", f"thigh_{side}", f"shank_{side}", (0, 0, -THIGH), (0, 1, 0),
          LIM["knee"], comment="knee: passive in the tree, driven by knee_act through the closure knee_loop")
    body(f"shank_{side}", 1.6, (0, 0, -0.20), "box", (0.07, 0.08, 0.40), "shank structure")
    seg(f"shank_{side}", (-0.015, 0, -0.05), (-0.015, 0, -0.38), 0.075)   # wraps the two ankle actuators too
    joint(f"knee_crank_fixed_{side}", "fixed", f"shank_{side}", f"knee_crank_{side}", KNEE_CRANK)
    body(f"knee_crank_{side}", 0.08, (0, 0, 0), "box", (0.03, 0.04, 0.03), "crank pin boss (closure frame)")
    # ankle actuators: universal joint on the shank, housing (motor + screw), push rod (prismatic)
    for tag, sy in (("lat", s), ("med", -s)):
        top = (ACT_X, sy * ACT_Y, ACT_TOP_Z)
        joint(f"ankle_act_{tag}_u1_{side}", "revolute", f"shank_{side}", f"ankle_act_{tag}_cross_{side}", top,
              (0, 1, 0), (ANKLE_U1_LIM[0], ANKLE_U1_LIM[1], 0.0, 20.0),
              comment=f"ankle actuator ({'lateral' if tag == 'lat' else 'medial'}): universal joint = u1 (y) then u2 (x)")
        body(f"ankle_act_{tag}_cross_{side}", 0.02, (0, 0, 0), "box", (0.02, 0.02, 0.02), "cardan cross")
        joint(f"ankle_act_{tag}_u2_{side}", "revolute", f"ankle_act_{tag}_cross_{side}",
              f"ankle_act_{tag}_housing_{side}", (0, 0, 0), (1, 0, 0),
              (ANKLE_U2_LIM[0], ANKLE_U2_LIM[1], 0.0, 20.0))
        body(f"ankle_act_{tag}_housing_{side}", 0.55, (0, 0, -0.10), "cyl", (0.025, 0.20, "z"),
             "motor + roller screw")
        seg(f"ankle_act_{tag}_housing_{side}", (0, 0, -0.01), (0, 0, -0.19), 0.025, ssv=False)
        joint(f"ankle_act_{tag}_{side}", "prismatic", f"ankle_act_{tag}_housing_{side}",
              f"ankle_act_{tag}_rod_{side}", (0, 0, -ACT_NUT_DROP), (0, 0, -1),
              (ANKLE_ACT_LIM[0], ANKLE_ACT_LIM[1], 3000.0, 0.3),
              comment="ankle linear actuator: q = push-rod extension (m), positive pushes the heel down")
        body(f"ankle_act_{tag}_rod_{side}", 0.12, (0, 0, -ACT_ROD / 2), "cyl", (0.008, ACT_ROD, "z"), "push rod")
        seg(f"ankle_act_{tag}_rod_{side}", (0, 0, 0), (0, 0, -ACT_ROD), 0.01, ssv=False)
    # ankle: universal joint, pitch then roll (passive in the tree)
    joint(f"ankle_pitch_{side}", "revolute", f"shank_{side}", f"ankle_cross_{side}", (0, 0, -SHANK), (0, 1, 0),
          LIM["ankle_pitch"], comment="ankle: passive universal joint (pitch, then roll), driven by the two actuators")
    body(f"ankle_cross_{side}", 0.10, (0, 0, 0), "box", (0.04, 0.04, 0.04), "ankle cardan cross")
    joint(f"ankle_roll_{side}", "revolute", f"ankle_cross_{side}", f"foot_body_{side}", (0, 0, 0), (1, 0, 0),
          lim_of("ankle_roll", side))
    fx = (HEEL_X + TOE_JOINT_X) / 2
    body(f"foot_body_{side}", 1.1, (fx, 0, -0.055), "box", (TOE_JOINT_X - HEEL_X, FOOT_W, 0.05),
         "foot plate + 6-axis force/torque sensor")
    for yy in (0.03, -0.03):
        seg(f"foot_body_{side}", (HEEL_X + 0.03, yy, -0.05), (TOE_JOINT_X - 0.03, yy, -0.05), 0.03)
    joint(f"sole_fixed_{side}", "fixed", f"foot_body_{side}", f"foot_{side}", (fx, 0, -ANKLE_H),
          comment="controller frame: centre of the rear sole, on the ground plane")
    joint(f"toe_{side}", "revolute", f"foot_body_{side}", f"toe_link_{side}", (TOE_JOINT_X, 0, -0.06), (0, 1, 0),
          lim_of("toe", side))
    body(f"toe_link_{side}", 0.2, (TOE_LEN / 2, 0, -0.01), "box", (TOE_LEN, 0.11, 0.02), "toe segment")
    seg(f"toe_link_{side}", (0.035, -0.03, 0.0), (0.035, 0.03, 0.0), 0.02)


HEADER = """Lola-like biped (TUM "Lola", Lohmeier et al. ICRA 2009), written for mbgen.
GENERATED by robots/lola/make_lola.py - edit that script, not this file. Sources and derivations:
robots/lola/README.md. No third-party file was copied.

This URDF is the SPANNING TREE. The loops are closed by the joints in lola.yaml (closures):
  knee_loop_l/r  (revolute)  knee_rod -> knee_crank          (knee slider-crank)
  ankle_lat_l/r, ankle_med_l/r (spherical) ankle_act_*_rod -> foot_body  (two U-P-S ankle actuators)
Nominal pose = all joint values 0 (straight legs, feet flat, pelvis frame 1.04 m above the soles):
every closure's two frames coincide there (check_closures.py).
Actuated: hip_yaw/roll/pitch, knee_act (prismatic), ankle_act_lat/med (prismatic), toe per leg;
trunk_yaw, trunk_roll; shoulder_pitch/roll, elbow per arm; head_pan, head_tilt (24).
Passive tree joints (effort 0): knee, ankle_pitch/roll, knee_rod_joint, ankle_act_*_u1/u2.
Inertias: homogeneous boxes/cylinders/spheres about their centres (listed in README.md).
"""


def write_urdf(path):
    u = Urdf("lola", header=HEADER)
    # links in tree order: emit link, then joints after all links (URDF order does not matter)
    names_with_frames = {"foot_l", "foot_r"}
    for name, mass, com, I in LINKS:
        u.link(name, mass, com, I, collisions=COLL_EXTRA.get(name, []))
    for name in sorted(names_with_frames):
        u.link(name)   # massless frame links (fixed): the sole frames
    for j in JOINTS:
        u.joint(**j)
    u.write(path)
    return u


def yaml_point(p):
    return "[" + ", ".join(vec([x]) for x in p) + "]"


# The legs-only scene (lola_legs.yaml): trunk, head and arms welded at 0 (docs/extras.md, "Model
# reductions"), for a simulation of walking that does not move them.
UPPER_BODY = ["trunk_yaw", "trunk_roll", "head_pan", "head_tilt", "shoulder_pitch_l", "shoulder_roll_l", "elbow_l",
              "shoulder_pitch_r", "shoulder_roll_r", "elbow_r"]


def write_yaml(path, legs_only=False, transmission=False):
    L = []
    w = L.append
    w("# Extras for lola.urdf (mbgen schema, docs/extras.md). Generated by make_lola.py; see README.md.")
    if legs_only:
        w("# The legs-only scene: the upper body welded (scene: lock), the simulation's functions alone.")
    if transmission:
        w("# The knee and ankle linkages replaced by their transmissions (scene: loops): a tree, the")
        w("# actuators' map from the outputs in the runtime's TransmissionMap.")
    w(("robot: lola_legs_transmission" if transmission else "robot: lola_legs") if legs_only else "robot: lola")
    w("base: floating")
    w("")
    w("# Loop closures. The URDF is the spanning tree; these joints close the loops.")
    w("# Nominal pose (all tree joints 0, actuators at 0 travel): every pair of closure frames coincides")
    w("# (check_closures.py prints the residuals).")
    w("closures:")
    for side, s in (("l", 1), ("r", -1)):
        w(f"  # knee slider-crank ({side}): thigh - nut (prismatic) - rod - shank crank pin - knee - thigh")
        w(f"  - name: knee_loop_{side}")
        w("    type: revolute")
        w(f"    parent: knee_rod_{side}")
        w(f"    child: knee_crank_{side}")
        w(f"    parent_origin: {{xyz: [0, 0, {vec([-KNEE_ROD])}], rpy: [0, 0, 0]}}")
        w("    child_origin: {xyz: [0, 0, 0], rpy: [0, 0, 0]}")
        w("    axis: [0, 1, 0]")
        for tag, sy in (("lat", s), ("med", -s)):
            w(f"  # ankle actuator {tag} ({side}): shank - U - housing - P - rod - ball joint - heel")
            w(f"  - name: ankle_{tag}_{side}")
            w("    type: spherical")
            w(f"    parent: ankle_act_{tag}_rod_{side}")
            w(f"    child: foot_body_{side}")
            w(f"    parent_origin: {{xyz: [0, 0, {vec([-ACT_ROD])}], rpy: [0, 0, 0]}}")
            w(f"    child_origin: {{xyz: {yaml_point((ACT_X, sy * ACT_Y, 0.0))}, rpy: [0, 0, 0]}}")
            w("    axis: [0, 0, 1]")
    w("")
    w("# Actuated joints: the linear actuators (knee, ankle) and every directly driven rotary joint.")
    ind = []
    for side in ("l", "r"):
        ind += [f"hip_yaw_{side}", f"hip_roll_{side}", f"hip_pitch_{side}", f"knee_act_{side}",
                f"ankle_act_lat_{side}", f"ankle_act_med_{side}", f"toe_{side}"]
    ind += ["trunk_yaw", "trunk_roll"]
    for side in ("l", "r"):
        ind += [f"shoulder_pitch_{side}", f"shoulder_roll_{side}", f"elbow_{side}"]
    ind += ["head_pan", "head_tilt"]
    w("independent: [" + ", ".join(ind) + "]")
    w("")
    w("# Harmonic drives on the rotary joints: reflected rotor inertia = gear_ratio^2 * rotor_inertia.")
    w("# The roller-screw actuators are not listed (see README, 'Drives'); to include them:")
    w("#  - {joint: knee_act_l, gear_ratio: 2513.27, rotor_inertia: 1.5e-5, model: armature}  # 2.5 mm lead")
    w("#  - {joint: ankle_act_lat_l, gear_ratio: 3141.59, rotor_inertia: 6.0e-6, model: armature}  # 2 mm lead")
    w("drives:")
    order = ["hip_yaw", "hip_roll", "hip_pitch", "toe"]
    for side in ("l", "r"):
        for j in order:
            g, r = DRIVES[j]
            w(f"  - {{joint: {j}_{side}, gear_ratio: {g}, rotor_inertia: {r:.1e}, model: armature}}")
    for j in ("trunk_yaw", "trunk_roll"):
        g, r = DRIVES[j]
        w(f"  - {{joint: {j}, gear_ratio: {g}, rotor_inertia: {r:.1e}, model: armature}}")
    for side in ("l", "r"):
        for j in ("shoulder_pitch", "shoulder_roll", "elbow"):
            g, r = DRIVES[j]
            w(f"  - {{joint: {j}_{side}, gear_ratio: {g}, rotor_inertia: {r:.1e}, model: armature}}")
    for j in ("head_pan", "head_tilt"):
        g, r = DRIVES[j]
        w(f"  - {{joint: {j}, gear_ratio: {g}, rotor_inertia: {r:.1e}, model: armature}}")
    w("")
    w("# Swept-sphere volumes per major segment (link frames, metres).")
    w("ssv:")
    for link_name, prims in SSV.items():
        items = []
        for kind, pts, r in prims:
            if kind == "point":
                items.append(f"{{point: {yaml_point(pts[0])}, radius: {vec([r])}}}")
            else:
                items.append(f"{{line: [{yaml_point(pts[0])}, {yaml_point(pts[1])}], radius: {vec([r])}}}")
        w(f"  {link_name}:")
        for it in items:
            w(f"    - {it}")
    w("")
    w("scene:")
    w("  outputs:")
    if legs_only:
        w("    - forward_dynamics")
        w("    - simulation")
        w(f"  lock: [{', '.join(UPPER_BODY)}]")
        if transmission:
            w("  loops: transmission")
    else:
        for o in ("forward_kinematics", "forward_dynamics", "inverse_dynamics", "mass_matrix", "center_of_mass",
                  "centroidal_momentum"):
            w(f"    - {o}")
        w("    - jacobians: [foot_l, foot_r, torso]")
        w("    - distances")
    w("  collision:")
    w("    margin: 0.05")
    w("    exclude: [[pelvis, torso], [pelvis, thigh_l], [pelvis, thigh_r], [torso, upper_arm_l], "
      "[torso, upper_arm_r], [foot_body_l, shank_l], [foot_body_r, shank_r], [toe_link_l, foot_body_l], "
      "[toe_link_r, foot_body_r]]")
    w("    prune_samples: 20000")
    w("  # Ground contact for simulation (docs/simulation.md): the vertex spheres of the feet's and")
    w("  # toes' SSVs (12), Hunt-Crossley normal force and regularised Coulomb friction.")
    w("  contact:")
    w("    links: [foot_body_l, toe_link_l, foot_body_r, toe_link_r]")
    w("    stiffness: 2.0e7        # N/m^1.5")
    w("    damping: 2.0            # s/m")
    w("    exponent: 1.5")
    w("    friction: 0.8")
    w("    stiction_velocity: 1.0e-3   # m/s")
    w("    ground: {normal: [0, 0, 1], offset: 0}")
    w("  scalar: double")
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    build()
    u = write_urdf(os.path.join(HERE, "lola.urdf"))
    write_yaml(os.path.join(HERE, "lola.yaml"))
    write_yaml(os.path.join(HERE, "lola_legs.yaml"), legs_only=True)
    write_yaml(os.path.join(HERE, "lola_legs_transmission.yaml"), legs_only=True, transmission=True)
    total = sum(m for _, m, _, _ in LINKS)
    print(f"lola: {len(LINKS)} bodies with mass, total mass {total:.3f} kg, pelvis frame at z = {PELVIS_Z:.3f} m")
    print("knee_act travel over the knee range: [%.4f, %.4f] m -> limit %s" % (RANGES[0], RANGES[1], KNEE_ACT_LIM))
    print("knee_rod angle: [%.4f, %.4f] rad -> limit %s" % (RANGES[2], RANGES[3], KNEE_ROD_LIM))
    print("ankle actuator extension over the ankle box: [%.4f, %.4f] m -> limit %s" % (RANGES[4], RANGES[5], ANKLE_ACT_LIM))
    print("ankle actuator u1: [%.4f, %.4f] -> %s; u2: [%.4f, %.4f] -> %s" % (RANGES[6], RANGES[7], ANKLE_U1_LIM,
                                                                            RANGES[8], RANGES[9], ANKLE_U2_LIM))
    if "--table" in sys.argv:
        for name, m, com, desc, rule in MASS_TABLE:
            print(f"| {name} | {m:g} | ({', '.join('%g' % c for c in com)}) | {desc} | {rule} |")
