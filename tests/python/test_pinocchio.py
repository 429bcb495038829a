"""vito's kinematics and dynamics against Pinocchio, an independent rigid-body library.

On the shipped robots and on robots of example-robot-data (18 in all), at seeded random
configurations: every link's world pose (≤ 1e-12 m and 1e-12 in each rotation entry), the
mass matrix, the generalised gravity and the inverse dynamics (≤ 1e-9 relative to the
largest entry); and the committed plans of the hopper and of LittleDog's step against the
discrete Euler–Lagrange equations of the midpoint rule built from Pinocchio's mass matrix,
gravity and contact Jacobians, with each contact's impulse from the trajectory file's world
columns `<c>_fx/_fy/_fz` (≤ 1e-8 N·s; LittleDog's feet cross the step's face, where the
surface's frame turns). Each check also runs on an input changed on
purpose (a coordinate moved by 1e-6, every link 1 % heavier, the base's angles in the wrong
order) and must see it. How vito's coordinates map onto Pinocchio's joints:
pinocchio_oracle.py.

Pinocchio (PyPI `pin`) and example-robot-data come from vendor-config/install-python.sh;
these tests skip, saying so, where they could not be installed.
"""

import csv
import math
import tomllib
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import ROOT
from pinocchio_oracle import Pair, example_robot_data_dir

pin = pytest.importorskip(
    "pinocchio",
    reason="Pinocchio is not installed (PyPI `pin`; vendor-config/install-python.sh installs "
    "it where PyPI is reachable)",
)

ROBOTS = ROOT / "problems" / "robots"
SHIPPED = [
    ("hopper_2d", ROBOTS / "hopper_2d.urdf", "fixed"),
    ("brick", ROBOTS / "brick.urdf", "floating"),
    ("littledog", ROBOTS / "littledog" / "LittleDog.normalized.urdf", "floating"),
    (
        "spring_flamingo",
        ROBOTS / "spring_flamingo" / "spring_flamingo_passive_ankle.normalized.urdf",
        "planar",
    ),
    ("hamr_simple", ROBOTS / "hamr" / "HAMRSimple_scaled.normalized.urdf", "floating"),
    ("hamr", ROBOTS / "hamr" / "HAMR_scaledV2.normalized.urdf", "floating"),
]
# example-robot-data's robots that vito loads. Not here: bolt (its feet have mass 0 and a
# rotational inertia: vito reads mass 0 as a massless frame, Pinocchio keeps the inertia, a
# 1e-6 relative difference in M), kinova (a transmission on a fixed joint, which vito
# refuses), icub (urdf-rs refuses its `<gazebo>` plugins), anymal_c (links named as joints,
# which pinocchio.appendModel refuses).
EXAMPLE_ROBOT_DATA = [
    ("solo12", "solo_description/robots/solo12.urdf", "floating"),
    ("anymal_b", "anymal_b_simple_description/robots/anymal.urdf", "floating"),
    ("go2", "go2_description/urdf/go2.urdf", "floating"),
    ("hyq", "hyq_description/robots/hyq_no_sensors.urdf", "floating"),
    ("go1", "go1_description/urdf/go1.urdf", "floating"),
    ("a1", "a1_description/urdf/a1.urdf", "floating"),
    ("talos_reduced", "talos_data/robots/talos_reduced.urdf", "floating"),
    ("romeo", "romeo_description/urdf/romeo_small.urdf", "floating"),
    ("g1", "g1_description/urdf/g1_29dof_rev_1_0.urdf", "floating"),
    ("panda", "panda_description/urdf/panda.urdf", "fixed"),  # a <mimic> finger
    ("ur5", "ur_description/urdf/ur5_robot.urdf", "fixed"),
    ("tiago", "tiago_description/robots/tiago_no_hand.urdf", "fixed"),
]
ROBOT_IDS = [name for name, _, _ in SHIPPED + EXAMPLE_ROBOT_DATA]
SAMPLES = 5


def pair(name, **options):
    for robot, path, base in SHIPPED:
        if robot == name:
            return Pair(pin, path, base, **options)
    for robot, relative, base in EXAMPLE_ROBOT_DATA:
        if robot == name:
            data = example_robot_data_dir()
            if data is None:
                pytest.skip(
                    "example-robot-data is not installed (PyPI `example-robot-data`; "
                    "vendor-config/install-python.sh installs it where PyPI is reachable)"
                )
            return Pair(pin, data / relative, base, **options)
    raise KeyError(name)


def configurations(n, seed):
    """Seeded configurations, every coordinate in [−1, 1] (m or rad)."""
    rng = np.random.default_rng(seed)
    return [rng.uniform(-1.0, 1.0, n) for _ in range(SAMPLES)]


def links(p):
    """vito's links that Pinocchio has as bodies (all but the URDF's root `world` link of a
    fixed-base URDF that names one, which Pinocchio merges into its universe)."""
    return [
        link
        for link in p.vito.link_names
        if p.model.existFrame(link, pin.BODY)
    ]


def kinematics_error(p, qs, shift=0.0):
    """The largest difference in any link's world position [m] or rotation entry; Pinocchio
    is given q with its last coordinate moved by `shift`."""
    worst = 0.0
    names = links(p)
    assert len(names) >= min(3, len(p.vito.link_names))
    for q in qs:
        moved = q.copy()
        moved[-1] += shift
        for link in names:
            rotation, position = p.frame(link, moved)
            worst = max(
                worst,
                np.abs(p.vito.frame_position(link, q) - position).max(),
                np.abs(p.vito.frame_rotation(link, q) - rotation).max(),
            )
    return worst


def dynamics_errors(p, qs, seed):
    """The largest relative differences (to the largest entry) of M, g and the inverse
    dynamics (springs cancel: vito's at (q, v, a) less its own at rest, plus gravity)."""
    rng = np.random.default_rng(seed + 1)
    worst = {"mass_matrix": 0.0, "gravity": 0.0, "inverse_dynamics": 0.0}
    for q in qs:
        m, g = p.mass_matrix(q), p.gravity(q)
        worst["mass_matrix"] = max(
            worst["mass_matrix"], np.abs(p.vito.mass_matrix(q) - m).max() / np.abs(m).max()
        )
        worst["gravity"] = max(
            worst["gravity"], np.abs(p.vito.gravity(q) - g).max() / np.abs(g).max()
        )
        v, a = rng.uniform(-1.0, 1.0, p.n), rng.uniform(-1.0, 1.0, p.n)
        zero = np.zeros(p.n)
        ours = (
            p.vito.inverse_dynamics(q, v, a)
            - p.vito.inverse_dynamics(q, zero, zero)
            + p.vito.gravity(q)
        )
        theirs = p.inverse_dynamics(q, v, a)
        worst["inverse_dynamics"] = max(
            worst["inverse_dynamics"], np.abs(ours - theirs).max() / np.abs(theirs).max()
        )
    return worst


@pytest.mark.parametrize("name", ROBOT_IDS)
def test_link_poses_match_pinocchio(name):
    p = pair(name)
    qs = configurations(p.n, seed=len(name))
    assert kinematics_error(p, qs) <= 1e-12
    # Pinocchio at q with the last coordinate moved by 1e-6 (m or rad): seen.
    assert kinematics_error(p, qs, shift=1e-6) > 1e-8


@pytest.mark.parametrize("name", ROBOT_IDS)
def test_mass_matrix_gravity_and_inverse_dynamics_match_pinocchio(name):
    p = pair(name)
    qs = configurations(p.n, seed=len(name))
    errors = dynamics_errors(p, qs, seed=len(name))
    assert max(errors.values()) <= 1e-9, errors
    # Every link 1 % heavier in Pinocchio: seen in M and g.
    p.make_heavier(1.01)
    heavier = dynamics_errors(p, qs, seed=len(name))
    assert heavier["mass_matrix"] > 1e-4 and heavier["gravity"] > 1e-3, heavier


def test_the_floating_bases_angles_are_mapped_in_their_order():
    """The composite root joint turns yaw, then pitch, then roll: given in vito's order
    (roll, pitch, yaw) instead, the poses differ by whole radians' worth."""
    right = pair("littledog")
    wrong = pair(
        "littledog",
        base_order=["base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw"],
    )
    qs = configurations(right.n, seed=3)
    assert kinematics_error(right, qs) <= 1e-12
    assert kinematics_error(wrong, qs) > 1e-2


# --- A plan's discrete dynamics ------------------------------------------------------------


def read_plan(path):
    """A trajectory.csv as {column name without unit: array} (empty cells NaN)."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header = [h.split(" [")[0] for h in rows[0]]
    values = np.array(
        [[float(x) if x else math.nan for x in row] for row in rows[1:]], dtype=float
    )
    return {name: values[:, i] for i, name in enumerate(header)}


def del_residuals(p, plan, contacts):
    """Every dynamics row of the plan (the first step's and the DEL rows at knots 2..N−1 of
    docs/reference-problems.md) from Pinocchio's M, g, ∂T/∂q and contact Jacobians:

      Ld(qa, qb, h) = h·[½ v̄ᵀM(q̄)v̄ − V(q̄)],  q̄ = (qa + qb)/2,  v̄ = (qb − qa)/h, so
      D1Ld = (h/2)·(∂T/∂q − g)(q̄, v̄) − M(q̄)v̄,  D2Ld = (h/2)·(∂T/∂q − g)(q̄, v̄) + M(q̄)v̄;
      Fd = h·B·u (no damping in these robots), half to each end knot;
      J(q_{k+1})ᵀλ_k = Σ_i (∂p_i/∂q)ᵀ F_i with F_i the trajectory file's world impulse of
      contact i (`<c>_fx`, `_fy`, `_fz`), whatever the terrain's frame.

    Returns the rows (N−1 × n), in N·s and N·m·s."""
    names = p.vito.coordinate_names
    q = np.column_stack([plan[c] for c in names])
    v0 = np.array([plan[f"{c}_dot"][0] for c in names])
    t = plan["time"]
    h = np.diff(t)
    knots = len(t)
    inputs = [c for c in names if f"u_{c}" in plan]
    u = np.zeros((knots - 1, p.n))
    for c in inputs:
        u[:, names.index(c)] = plan[f"u_{c}"][:-1]

    def slots(k):
        """(D1Ld, D2Ld) of interval k."""
        qa, qb, hk = q[k], q[k + 1], h[k]
        qm, vm = 0.5 * (qa + qb), (qb - qa) / hk
        common = 0.5 * hk * (p.kinetic_energy_gradient(qm, vm) - p.gravity(qm))
        mv = p.mass_matrix(qm) @ vm
        return common - mv, common + mv

    def impulse(k):
        total = np.zeros(p.n)
        for name, link, point in contacts:
            jac, _ = p.point_jacobian(link, point, q[k + 1])
            for axis, row in zip("xyz", jac):
                total += row * plan[f"{name}_f{axis}"][k]
        return total

    d = [slots(k) for k in range(knots - 1)]
    rows = [p.mass_matrix(q[0]) @ v0 + d[0][0] + 0.5 * h[0] * u[0] + impulse(0)]
    for k in range(1, knots - 1):
        rows.append(
            d[k - 1][1] + d[k][0] + 0.5 * (h[k - 1] * u[k - 1] + h[k] * u[k]) + impulse(k)
        )
    return np.array(rows)


def hopper_plan():
    urdf = ROBOTS / "hopper_2d.urdf"
    foot = ET.parse(urdf).getroot().find("link[@name='foot']/collision/origin")
    point = [float(x) for x in foot.get("xyz").split()]
    plan = read_plan(ROOT / "results" / "motion" / "hopper_2d" / "trajectory.csv")
    return urdf, "fixed", plan, [("foot_contact", "foot", point)]


def littledog_plan():
    with open(ROOT / "problems" / "littledog_step.toml", "rb") as f:
        problem = tomllib.load(f)
    contacts = [(c["name"], c["link"], c["point"]) for c in problem["contacts"]["point"]]
    plan = read_plan(ROOT / "results" / "motion" / "littledog_step" / "trajectory.csv")
    urdf = ROBOTS / "littledog" / "LittleDog.normalized.urdf"
    return urdf, "floating", plan, contacts


@pytest.mark.parametrize("plan", [hopper_plan, littledog_plan], ids=["hopper", "littledog_step"])
def test_a_committed_plan_satisfies_pinocchios_discrete_dynamics(plan):
    urdf, base, trajectory, contacts = plan()
    p = Pair(pin, urdf, base)
    residual = np.abs(del_residuals(p, trajectory, contacts)).max()
    assert residual <= 1e-8
    # The same plan with every link 1 % heavier does not balance.
    p.make_heavier(1.01)
    assert np.abs(del_residuals(p, trajectory, contacts)).max() > 1e-4
