"""A plan replayed in MuJoCo: the problem's world as a MuJoCo model, the plan's inputs played
with PD tracking of its configurations, and how far the motion ends from the plan.

Needs the `mujoco` package (the optional extra: ``pip install vito[mujoco]``)::

    import vito, vito.mujoco
    problem = vito.Problem("problems/hopper_2d.toml")
    replay = vito.mujoco.replay(problem, problem.solve(), gains={"all": (100.0, 10.0)})
    replay.end_deviation          # [m] the base's distance from the plan's at the end

The model (`model(problem)`) is built by vito from the robot as vito reads it
(`vito._vito.mujoco_model`): every joint named after its coordinate (a floating base is one
body with slides x, y, z and hinges about z, y, x: vito's Trans(x, y, z)·Rz(yaw)·Ry(pitch)·
Rx(roll)), the contacts as spheres (a point contact a sphere of 1 mm), the ground plane and
the problem's steps as boxes, the problem's gravity, one motor per input. See docs/python.md.
"""

from __future__ import annotations

import dataclasses

import numpy as np

try:
    import mujoco as _mujoco
except ImportError as _error:  # pragma: no cover - depends on the environment
    raise ImportError(
        "vito.mujoco needs the `mujoco` package: pip install 'vito[mujoco]' (or pip install "
        "mujoco)"
    ) from _error

from . import _vito

__all__ = ["Replay", "model", "replay"]


def model(problem, timestep=0.001):
    """The `mujoco.MjModel` of `problem`'s world (a `vito.Problem`), stepped every `timestep`
    seconds (written in the problem's time unit)."""
    built = _vito.mujoco_model(problem, timestep)
    return _mujoco.MjModel.from_xml_string(built["xml"])


@dataclasses.dataclass(frozen=True)
class Replay:
    """A plan played in MuJoCo, recorded at every control update and at the end.

    `time` (K), `q`, `v` (K × n, vito's coordinates in vito's order), `u` (K − 1 × m, the
    PD's input at each record), `plan_q` (K × n: the plan's configuration
    at the same times, linear between its knots), `deviation` (K: the distance [length
    unit] between the base's position, its `translation_coordinates`, and the plan's),
    `end_deviation` (its last value), `coordinate_names`, `input_names`,
    `translation_coordinates`, and the `mujoco` `model` and `data` at the end."""

    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    u: np.ndarray
    plan_q: np.ndarray
    deviation: np.ndarray
    coordinate_names: list
    input_names: list
    translation_coordinates: list
    model: object
    data: object

    @property
    def end_deviation(self) -> float:
        return float(self.deviation[-1])


def _gains(gains, input_names):
    """(kp, kd) per input from {"all": (kp, kd), name: (kp, kd)} (a name overrides "all")."""
    if not isinstance(gains, dict):
        raise TypeError(f"gains must be a dict of (kp, kd) by input name, got {type(gains).__name__}")
    unknown = sorted(set(gains) - set(input_names) - {"all"})
    if unknown:
        raise ValueError(
            f"no input {', '.join(map(repr, unknown))}; the inputs are: {', '.join(input_names)}"
        )
    out = np.zeros((len(input_names), 2))
    for i, name in enumerate(input_names):
        kp, kd = gains.get(name, gains.get("all", (0.0, 0.0)))
        kp, kd = float(kp), float(kd)
        if not (np.isfinite(kp) and np.isfinite(kd) and kp >= 0 and kd >= 0):
            raise ValueError(f"gains for {name!r} must be finite and ≥ 0, got ({kp}, {kd})")
        out[i] = kp, kd
    return out


def replay(problem, solution, gains, rate=None, timestep=0.001, duration=None):
    """Plays `solution` (a `vito.Solution`, or any result with `time`, `q`, `v`, `u` and their
    names) of `problem` (a `vito.Problem`) in MuJoCo with PD tracking: on each input,
    u = u_ref + kp (q_ref − q) + kd (v_ref − v), with q_ref linear between the plan's knots,
    v_ref its slope and u_ref the plan's input of the interval, held over it as the plan
    holds it. The PD is MuJoCo's own (each motor's bias −kp q − kd q̇, its control u_ref +
    kp q_ref + kd v_ref), so MuJoCo reads q and q̇ at every step and its `implicitfast`
    integrator treats the damping implicitly: stable at gains an explicit PD sampled at the
    plan's knots is not. The reference is updated every 1/`rate` seconds (default: every
    MuJoCo step). `gains`: {"all": (kp, kd), input name: (kp, kd)} (a name overrides "all";
    an input without gains gets u_ref alone). `duration` defaults to the plan's; MuJoCo steps
    every `timestep` seconds. The robot starts at the plan's first configuration and
    velocity. Returns a `Replay`."""
    built = _vito.mujoco_model(problem, timestep)
    m = _mujoco.MjModel.from_xml_string(built["xml"])
    d = _mujoco.MjData(m)
    names = list(solution.coordinate_names)
    inputs = list(solution.input_names)
    kpkd = _gains(gains, inputs)
    t_plan = np.asarray(solution.time, dtype=float)
    q_plan = np.asarray(solution.q, dtype=float)
    u_plan = np.asarray(solution.u, dtype=float).reshape(len(t_plan) - 1, len(inputs))
    qadr = np.array([m.jnt_qposadr[m.joint(name).id] for name in names])
    vadr = np.array([m.jnt_dofadr[m.joint(name).id] for name in names])
    actuator = np.array([m.actuator(name).id for name in inputs], dtype=int)
    c = np.array([names.index(name) for name in inputs], dtype=int)
    for a, (kp, kd) in zip(actuator, kpkd):
        m.actuator_biastype[a] = _mujoco.mjtBias.mjBIAS_AFFINE
        m.actuator_biasprm[a, :3] = [0.0, -kp, -kd]
    dt = built["timestep"]
    period = dt if rate is None else 1.0 / float(rate)
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"rate must be a positive number, got {rate!r}")
    substeps = max(1, int(round(period / dt)))
    end = t_plan[-1] if duration is None else float(duration)
    updates = int(round((end - t_plan[0]) / (substeps * dt)))

    def reference(t):
        j = int(np.clip(np.searchsorted(t_plan, t, side="right") - 1, 0, len(t_plan) - 2))
        h = t_plan[j + 1] - t_plan[j]
        s = np.clip((t - t_plan[j]) / h, 0.0, 1.0)
        slope = (q_plan[j + 1] - q_plan[j]) / h
        return q_plan[j] + s * (q_plan[j + 1] - q_plan[j]), slope, u_plan[j]

    d.qpos[qadr] = q_plan[0]
    d.qvel[vadr] = np.asarray(solution.v, dtype=float)[0]
    _mujoco.mj_forward(m, d)
    times, qs, vs, us = [], [], [], []
    t = t_plan[0]
    for k in range(updates + 1):
        q, v = d.qpos[qadr].copy(), d.qvel[vadr].copy()
        times.append(t)
        qs.append(q)
        vs.append(v)
        if k == updates:
            break
        q_ref, v_ref, u_ref = reference(t)
        d.ctrl[actuator] = u_ref + kpkd[:, 0] * q_ref[c] + kpkd[:, 1] * v_ref[c]
        us.append(u_ref + kpkd[:, 0] * (q_ref[c] - q[c]) + kpkd[:, 1] * (v_ref[c] - v[c]))
        for _ in range(substeps):
            _mujoco.mj_step(m, d)
        t = t_plan[0] + (k + 1) * substeps * dt
    times = np.array(times)
    qs, vs = np.array(qs), np.array(vs)
    plan_at = np.array([reference(min(t, t_plan[-1]))[0] for t in times])
    base = [names.index(name) for name in built["translation_coordinates"]]
    deviation = np.linalg.norm(qs[:, base] - plan_at[:, base], axis=1)
    return Replay(
        time=times,
        q=qs,
        v=vs,
        u=np.array(us).reshape(len(us), len(inputs)),
        plan_q=plan_at,
        deviation=deviation,
        coordinate_names=names,
        input_names=inputs,
        translation_coordinates=list(built["translation_coordinates"]),
        model=m,
        data=d,
    )
