"""`vito.mujoco`: the problem's world as a MuJoCo model and a plan replayed in it with PD
tracking, against vito's own mechanics and `vito simulate --track`."""

import numpy as np
import pytest

import vito
from conftest import HOPPER, ROOT

mujoco = pytest.importorskip(
    "mujoco",
    reason="MuJoCo is not installed (the optional extra `vito[mujoco]`; "
    "vendor-config/install-python.sh installs it where PyPI is reachable)",
)
import vito.mujoco as vm  # noqa: E402

LITTLEDOG = ROOT / "problems" / "littledog_step.toml"
GAINS = {"all": (100.0, 10.0)}


def plan(name):
    """A committed plan as a Solution-like record."""
    import pandas

    frame = pandas.read_csv(ROOT / "results" / "motion" / name / "trajectory.csv")
    columns = {c.split(" [")[0]: frame[c].to_numpy() for c in frame.columns}

    class Plan:
        coordinate_names = [c for c in columns if f"{c}_dot" in columns]
        input_names = [c[2:] for c in columns if c.startswith("u_")]
        time = columns["time"]
        q = np.column_stack([columns[c] for c in coordinate_names])
        v = np.column_stack([columns[f"{c}_dot"] for c in coordinate_names])
        u = np.column_stack([columns[f"u_{c}"] for c in input_names])[:-1]

    return Plan


def full_inertia(m, d):
    full = np.zeros((m.nv, m.nv))
    if hasattr(d, "qM"):  # MuJoCo before 3.3: mj_fullM(m, dst, qM)
        mujoco.mj_fullM(m, full, d.qM)
    else:
        mujoco.mj_fullM(m, d, full)
    return full


def test_the_model_has_vitos_mass_matrix_and_names():
    """MuJoCo's joint-space inertia of LittleDog's model at a seeded q is vito's M."""
    problem = vito.Problem(str(LITTLEDOG))
    m = vm.model(problem)
    d = mujoco.MjData(m)
    dynamics = vito.Dynamics(
        ROOT / "problems" / "robots" / "littledog" / "LittleDog.normalized.urdf", base="floating"
    )
    names = dynamics.coordinate_names
    q = np.random.default_rng(5).uniform(-1.0, 1.0, len(names))
    adr = [m.jnt_dofadr[m.joint(n).id] for n in names]
    d.qpos[[m.jnt_qposadr[m.joint(n).id] for n in names]] = q
    mujoco.mj_forward(m, d)
    full = full_inertia(m, d)
    ours = dynamics.mass_matrix(q)
    assert np.abs(full[np.ix_(adr, adr)] - ours).max() <= 1e-12 * np.abs(ours).max()
    assert m.nu == 12 and m.ngeom == 2 + 4  # ground, the step's box, four feet
    # Moving the roll hinge where yaw is (vito's order taken for MuJoCo's) is seen.
    swapped = list(names)
    swapped[3], swapped[5] = swapped[5], swapped[3]
    d.qpos[[m.jnt_qposadr[m.joint(n).id] for n in swapped]] = q
    mujoco.mj_forward(m, d)
    full = full_inertia(m, d)
    assert np.abs(full[np.ix_(adr, adr)] - ours).max() > 1e-3 * np.abs(ours).max()


def test_the_hoppers_plan_in_mujoco_ends_where_vito_simulate_track_does():
    """PD on the hopper's plan, MuJoCo against vito's own simulator with the same gains and
    the same implicit PD read every millisecond: the body ends 0.052 m and 0.046 m from the
    plan's (x, z)."""
    problem = vito.Problem(str(HOPPER))
    hopper = plan("hopper_2d")
    replay = vm.replay(problem, hopper, gains=GAINS)
    assert replay.translation_coordinates == ["x", "z"]
    assert replay.time[-1] == pytest.approx(hopper.time[-1])
    sim = vito.simulate(
        problem,
        track=ROOT / "results" / "motion" / "hopper_2d" / "trajectory.csv",
        gains=GAINS,
        feedback="implicit",
        rate=1000.0,
    )
    vito_end = np.linalg.norm(sim.q[-1][:2] - hopper.q[-1][:2])
    assert 0.03 < vito_end < 0.06
    assert replay.end_deviation < 0.07
    assert abs(replay.end_deviation - vito_end) < 0.015
    # The plan's inputs halved: MuJoCo's hopper ends far off.
    hopper.u = hopper.u * 0.5
    weak = vm.replay(problem, hopper, gains=GAINS)
    assert weak.end_deviation > 3 * replay.end_deviation


def test_gains_and_rates_are_checked():
    problem = vito.Problem(str(HOPPER))
    hopper = plan("hopper_2d")
    with pytest.raises(ValueError, match="no input 'knee'"):
        vm.replay(problem, hopper, gains={"knee": (1.0, 1.0)})
    with pytest.raises(ValueError, match="finite and ≥ 0"):
        vm.replay(problem, hopper, gains={"all": (-1.0, 1.0)})
    with pytest.raises(ValueError, match="rate must be a positive number"):
        vm.replay(problem, hopper, gains=GAINS, rate=-5.0)
    with pytest.raises(ValueError, match="time step must be a positive number"):
        vm.model(problem, timestep=0.0)
