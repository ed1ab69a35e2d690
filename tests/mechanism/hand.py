"""Hand-derived effective masses and free accelerations of the four test models.

Each value comes from the model's numbers (``tests/data/models/make_models.py``) through a closed
form written here, not through an engine: rigid-body kinematics of the contact point and
``1 / m_eff = 1/m + (s x n)^T I_W^-1 (s x n)`` for a free body, ``1 / m_eff = J M^-1 J^T`` with
``M`` assembled from the links' COM Jacobians for the leg.
"""

import importlib.util
import math
from pathlib import Path

import numpy as np

MODELS = Path(__file__).resolve().parents[1] / "data" / "models"
_spec = importlib.util.spec_from_file_location("make_models", MODELS / "make_models.py")
make_models = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_models)
G = make_models.G
PEND, CAPS, LEG, BOX = make_models.PEND, make_models.CAPS, make_models.LEG, make_models.BOX


def pendulum(push=0.0):
    """Tip sphere on the wall at the bottom of the swing; ``push`` N on the arm's COM toward the wall.

    The gap's row is -L (the tip moves along the normal at L per radian): m_eff = I_hinge / L^2;
    gravity has no moment at the bottom; a push F at the COM (distance L) gives F / m_eff.
    """
    p = PEND
    i_hinge = p["Iyy"] + p["m"] * p["L"] ** 2
    m_eff = i_hinge / p["L"] ** 2
    return m_eff, push * p["L"] ** 2 / i_hinge


def capsule():
    """Free capsule tilted by beta about y on its lower end: lever hl sin(beta) about the y axis."""
    c = CAPS
    lever = c["hl"] * math.sin(c["beta"])
    return 1.0 / (1.0 / c["m"] + lever**2 / c["I1"]), G


def _u(theta):
    return np.array([-math.sin(theta), 0.0, -math.cos(theta)])


def _du(theta):
    return np.array([-math.cos(theta), 0.0, math.sin(theta)])


def leg_dynamics():
    """``(M, J_n, tau_gravity)`` of the leg, coordinates (slide, hip, knee), at the model's pose."""
    g = LEG
    t1, t12 = g["q1"], g["q1"] + g["q2"]
    z = np.array([0.0, 0.0, 1.0])
    # COM Jacobians (3 x 3, columns slide, hip, knee) and angular-velocity rows about y.
    j0 = np.column_stack([z, np.zeros(3), np.zeros(3)])
    j1 = np.column_stack([z, 0.5 * g["l1"] * _du(t1), np.zeros(3)])
    j2 = np.column_stack([z, g["l1"] * _du(t1) + 0.5 * g["l2"] * _du(t12), 0.5 * g["l2"] * _du(t12)])
    w1, w2 = np.array([0.0, 1.0, 0.0]), np.array([0.0, 1.0, 1.0])
    M = g["M0"] * j0.T @ j0 + g["m1"] * j1.T @ j1 + g["m2"] * j2.T @ j2
    M += g["I1"] * np.outer(w1, w1) + g["I2"] * np.outer(w2, w2)
    foot = np.column_stack([z, g["l1"] * _du(t1) + g["l2"] * _du(t12), g["l2"] * _du(t12)])
    tau_g = -G * (g["M0"] * j0[2] + g["m1"] * j1[2] + g["m2"] * j2[2])
    return M, foot[2], tau_g


def leg(hip_push=0.0):
    """Foot on the floor: ``m_eff = 1/(J M^-1 J^T)``, accel ``-J M^-1 (tau_g + J_hip^T F)``."""
    M, J, tau_g = leg_dynamics()
    tau = tau_g + np.array([1.0, 0.0, 0.0]) * (-hip_push)
    minv_j = np.linalg.solve(M, J)
    return 1.0 / float(J @ minv_j), -float(minv_j @ tau)


def box_rotation():
    return make_models.rpy_matrix(*BOX["rpy"])


def box():
    """Free box on its lowest corner: 1/m + (s x z)^T (R I R^T)^-1 (s x z)."""
    b = BOX
    R = box_rotation()
    corners = [R @ c for c in make_models.box_corners(b["half"])]
    s = min(corners, key=lambda c: c[2])
    sxn = np.cross(s, [0.0, 0.0, 1.0])
    i_world = R @ np.diag(b["inertia"]) @ R.T
    return 1.0 / (1.0 / b["m"] + sxn @ np.linalg.solve(i_world, sxn)), G


def contact_points():
    """Where each pair touches, world axes: the tip's wall side, the capsule's lower end, the foot's
    lowest point, the box's lowest corner."""
    p, c, g, b = PEND, CAPS, LEG, BOX
    R = box_rotation()
    corners = [R @ x for x in make_models.box_corners(b["half"])]
    low = min(corners, key=lambda x: x[2])
    return {
        "pendulum": np.array([-p["r"], 0.0, 1.0 - p["L"]]),
        "capsule": np.array([-c["hl"] * math.sin(c["beta"]), 0.0, 0.0]),
        "leg": np.array([-g["l1"] * math.sin(g["q1"]) - g["l2"] * math.sin(g["q1"] + g["q2"]), 0.0, 0.0]),
        "box": np.array([low[0], low[1], 0.0]),
    }
