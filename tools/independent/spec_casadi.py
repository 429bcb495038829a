#!/usr/bin/env python3
"""Independent implementation of vito's reference problems (docs/reference-problems.md).

It shares no code with vito: closed-form energies straight from docs/reference-problems.md (hopper-2d, brick-3d)
or from its own URDF reader (spring-flamingo-walk, littledog-step, its "Extensions"),
symbolic derivatives by CasADi (SX), and CasADi's own bundled Ipopt. The results of the first
two, stored in tests/data/independent/*.json, are what vito's objective and trajectories are
compared against (tests/independent.rs). Regenerate with:

    pip install casadi==3.8.2
    python3 tools/independent/spec_casadi.py tests/data/independent

Timing (what `vito bench` runs for its CasADi column; one JSON line per problem):

    python3 tools/independent/spec_casadi.py --bench hopper-2d brick-3d spring-flamingo-walk littledog-step

`--initial NAME...` prints the values at the initial guess (docs/reference-problems.md lists them) instead.
The NLP follows "The nonlinear program all four share" line by line.
"""
import json
import math
import os
import sys
import time
import xml.etree.ElementTree as ET

import casadi as ca
import numpy as np

G = 9.81


def hopper():
    n, m = 4, 2
    q = ca.SX.sym("q", n)
    v = ca.SX.sym("v", n)
    x, z, th, r = q[0], q[1], q[2], q[3]
    foot = ca.vertcat(x + r * ca.sin(th), z - r * ca.cos(th))
    foot_dot = ca.jtimes(foot, q, v)
    T = 0.5 * 3.0 * (v[0] ** 2 + v[1] ** 2) + 0.5 * 0.3 * ca.sumsqr(foot_dot) + 0.5 * (0.75 + 0.075) * v[2] ** 2
    V = G * (3.0 * z + 0.3 * foot[1])
    phi = ca.vertcat(foot[1])  # one contact
    tangents = [ca.vertcat(foot[0])]  # nd = 2: +D, -D
    q1 = [0.0, 0.5, 0.0, 0.5]
    qN = [0.5, 0.5, 0.0, 0.5]
    lbq = [-ca.inf, 0.0, -ca.inf, 0.3]
    ubq = [ca.inf, ca.inf, ca.inf, 0.7]
    return dict(
        name="hopper_2d", n=n, m=m, q=q, v=v, T=T, V=V, phi=phi, tangents=tangents,
        B=np.array([[0, 0], [0, 0], [1, 0], [0, 1]], dtype=float),
        mu=0.8, N=21, h=0.05, q1=q1, qN_fixed=qN, v0=[0.0] * n,
        lbq=lbq, ubq=ubq, lbu=[-10.0, -100.0], ubu=[10.0, 100.0],
        alpha=100.0, Q=np.eye(4), R=np.diag([0.1, 0.01]), q_target=qN,
        guess_q=lambda k, N: [q1[i] + (qN[i] - q1[i]) * k / (N - 1) for i in range(n)],
    )


def rot(axis, a):
    c, s = ca.cos(a), ca.sin(a)
    if axis == "x":
        return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))
    if axis == "y":
        return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))
    return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))


def body_angular_velocity(R, q, v):
    """ω_b with skew(ω_b) = RᵀṘ, Ṙ = ∂R/∂q · v."""
    Rdot = ca.SX.zeros(3, 3)
    for i in range(3):
        for j in range(3):
            Rdot[i, j] = ca.jtimes(R[i, j], q, v)
    W = R.T @ Rdot
    return ca.vertcat(W[2, 1], W[0, 2], W[1, 0])


def brick():
    n, m = 6, 0
    q = ca.SX.sym("q", n)
    v = ca.SX.sym("v", n)
    a, b, c, mass = 0.2, 0.1, 0.05, 1.0
    R = rot("z", q[5]) @ rot("y", q[4]) @ rot("x", q[3])
    omega = body_angular_velocity(R, q, v)
    inertia = np.diag([mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c), mass / 12 * (a * a + b * b)])
    T = 0.5 * mass * ca.sumsqr(v[0:3]) + 0.5 * omega.T @ inertia @ omega
    V = mass * G * q[2]
    corners = [np.array([sx * a / 2, sy * b / 2, sz * c / 2]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    world = [q[0:3] + R @ p for p in corners]
    phi = ca.vertcat(*[w[2] for w in world])
    tangents = [ca.vertcat(w[0], w[1]) for w in world]  # nd = 4: +x, +y, -x, -y
    q1 = [0.0, 0.0, 0.25, 0.3, -0.2, 0.1]
    return dict(
        name="brick_3d", n=n, m=m, q=q, v=v, T=T, V=V, phi=phi, tangents=tangents,
        B=np.zeros((n, 0)), mu=0.5, N=41, h=0.025, q1=q1, qN_fixed=None,
        v0=[1.0, 0.0, 0.0, 2.0, 1.0, 0.0],
        lbq=[-ca.inf] * n, ubq=[ca.inf] * n, lbu=[], ubu=[],
        alpha=1000.0, Q=None, R=None, q_target=None,
        guess_q=lambda k, N: list(q1),
    )


ROBOTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "problems", "robots")


def _floats(text, default):
    return [float(t) for t in text.split()] if text is not None else list(default)


def _origin(elem):
    o = elem.find("origin") if elem is not None else None
    if o is None:
        return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    return _floats(o.get("xyz"), [0, 0, 0]), _floats(o.get("rpy"), [0, 0, 0])


def rpy_matrix(rpy):
    """R(rpy) = Rz(y)·Ry(p)·Rx(r), numeric."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def axis_rotation(axis, a):
    """Rot(axis, a) for a unit axis (Rodrigues; the coordinate axes exactly)."""
    for i, name in enumerate("xyz"):
        e = [0.0, 0.0, 0.0]
        e[i] = 1.0
        if list(axis) == e:
            return rot(name, a)
        e[i] = -1.0
        if list(axis) == e:
            return rot(name, -a)
    k = np.array(axis) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return ca.DM.eye(3) + ca.sin(a) * kx + (1 - ca.cos(a)) * (kx @ kx)


def urdf_robot(path, base):
    """Extension 3: configuration, link poses, energies, contacts and inputs of a URDF."""
    root = ET.parse(path).getroot()
    for elem in root.iter():  # LittleDog's file declares a default namespace (Drake's)
        elem.tag = elem.tag.rsplit("}", 1)[-1]
    links = {l.get("name"): l for l in root.findall("link")}
    joints = root.findall("joint")
    children = {}
    for j in joints:
        children.setdefault(j.find("parent").get("link"), []).append(j)
    child_links = {j.find("child").get("link") for j in joints}
    (root_link,) = [name for name in links if name not in child_links]
    movable = [j for j in joints if j.get("type") != "fixed"]
    nb = {"planar": 3, "floating": 6}[base]
    n = nb + len(movable)
    q = ca.SX.sym("q", n)
    v = ca.SX.sym("v", n)
    names = (["base_x", "base_z", "base_pitch"] if base == "planar"
             else ["base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw"])
    names += [j.get("name") for j in movable]
    index = {j.get("name"): nb + i for i, j in enumerate(movable)}
    if base == "planar":
        p0, r0 = ca.vertcat(q[0], 0, q[1]), rot("y", q[2])
    else:
        p0, r0 = q[0:3], rot("z", q[5]) @ rot("y", q[4]) @ rot("x", q[3])
    poses = {}

    def walk(link, p, r):
        poses[link] = (p, r)
        for j in children.get(link, []):
            xyz, rpy = _origin(j)
            pc = p + r @ np.array(xyz)
            rc = r @ rpy_matrix(rpy)
            if j.get("type") in ("revolute", "continuous"):
                ax = j.find("axis")
                rc = rc @ axis_rotation(_floats(ax.get("xyz") if ax is not None else None, [1, 0, 0]), q[index[j.get("name")]])
            elif j.get("type") != "fixed":
                raise ValueError("joint type %s not supported" % j.get("type"))
            walk(j.find("child").get("link"), pc, rc)

    walk(root_link, p0, r0)
    T, V = 0, 0
    for name, link in links.items():
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass = float(inertial.find("mass").get("value"))
        xyz, rpy = _origin(inertial)
        i = inertial.find("inertia")
        g = lambda k: float(i.get(k, "0"))
        inertia = np.array([[g("ixx"), g("ixy"), g("ixz")], [g("ixy"), g("iyy"), g("iyz")], [g("ixz"), g("iyz"), g("izz")]])
        p, r = poses[name]
        com = p + r @ np.array(xyz)
        rc = r @ rpy_matrix(rpy)
        com_dot = ca.jtimes(com, q, v)
        omega = body_angular_velocity(rc, q, v)
        T += 0.5 * mass * ca.sumsqr(com_dot) + 0.5 * omega.T @ inertia @ omega
        V += mass * G * com[2]
    for fe in root.iter("torsional_spring"):
        k, rest = float(fe.get("stiffness")), float(fe.get("rest_angle", "0"))
        V += 0.5 * k * (q[index[fe.find("joint").get("name")]] - rest) ** 2
    damping = np.zeros(n)
    lbq, ubq = [-ca.inf] * n, [ca.inf] * n
    effort = []
    for j in movable:
        d = j.find("dynamics")
        if d is not None and d.get("damping") is not None:
            damping[index[j.get("name")]] = float(d.get("damping"))
        lim = j.find("limit")
        if lim is not None and lim.get("lower") is not None:
            lbq[index[j.get("name")]] = float(lim.get("lower"))
            ubq[index[j.get("name")]] = float(lim.get("upper"))
    actuated = [t.find("joint").get("name") for t in root.findall("transmission")]
    B = np.zeros((n, len(actuated)))
    for col, name in enumerate(actuated):
        B[index[name], col] = 1.0
        lim = [j for j in movable if j.get("name") == name][0].find("limit")
        effort.append(float(lim.get("effort", "inf")) if lim is not None else math.inf)
    spheres = []
    for name, link in links.items():
        for c in link.findall("collision"):
            s = c.find("geometry/sphere")
            if s is not None and float(s.get("radius")) == 0.0:
                spheres.append((name, _origin(c)[0]))
    return dict(n=n, q=q, v=v, T=T, V=V, names=names, poses=poses, damping=damping,
                lbq=lbq, ubq=ubq, B=B, effort=effort, spheres=spheres)


def point(robot, link, xyz):
    p, r = robot["poses"][link]
    return p + r @ np.array(xyz)


def spring_flamingo():
    rb = urdf_robot(os.path.join(ROBOTS, "spring_flamingo", "spring_flamingo_passive_ankle.normalized.urdf"), "planar")
    n, m = rb["n"], rb["B"].shape[1]
    feet = [point(rb, link, xyz) for link, xyz in rb["spheres"]]
    delta = math.pi / 2 - 1.57075
    q1 = [0, 0.875, 0, 0, 0, delta, 0, 0, delta]
    qN = [-0.9] + q1[1:]
    ubq = list(rb["ubq"])
    ubq[1] = 0.876
    xg = qN + [0.0] * n
    N = 25

    def cost(qa, qb, h, u):
        xbar = ca.vertcat((qa + qb) / 2, (qb - qa) / h) - np.array(xg)
        return h * (0.1 * ca.dot(xbar, xbar) + ca.dot(u, u))

    return dict(
        name="spring_flamingo_walk", n=n, m=m, q=rb["q"], v=rb["v"], T=rb["T"], V=rb["V"],
        phi=ca.vertcat(*[f[2] for f in feet]), tangents=[ca.vertcat(f[0]) for f in feet],
        B=rb["B"], damping=rb["damping"], mu=1.0, N=N, h=None, T_window=(0.5, 2.5),
        q1=q1, qN_fixed=qN, v0=[0.0] * n, lbq=rb["lbq"], ubq=ubq,
        lbu=[-e for e in rb["effort"]], ubu=list(rb["effort"]), alpha=1e4, cost=cost,
        guess_q=lambda k, N: [q1[i] + (qN[i] - q1[i]) * k / (N - 1) for i in range(n)],
    )


def littledog():
    rb = urdf_robot(os.path.join(ROBOTS, "littledog", "LittleDog.normalized.urdf"), "floating")
    n, m = rb["n"], rb["B"].shape[1]
    legs = ["front_left", "front_right", "back_left", "back_right"]
    feet = [point(rb, leg + "_lower_leg", [(-0.0265 if leg.startswith("front") else 0.0265), 0.0, -0.0985]) for leg in legs]
    step = lambda x: 0.11 * 0.5 * (1 + ca.tanh((x - 0.25) / 0.005))
    home = {"front_left": (0.1, 1.0, -1.55), "front_right": (-0.1, 1.0, -1.55),
            "back_left": (0.1, -1.0, 1.55), "back_right": (-0.1, -1.0, 1.55)}
    q1 = [0.0] * n
    q1[2] = 0.136
    for leg, (roll, pitch, knee) in home.items():
        for joint, value in (("hip_roll", roll), ("hip_pitch", pitch), ("knee", knee)):
            q1[rb["names"].index(f"{leg}_{joint}")] = value
    qg = list(q1)
    qg[0], qg[2] = 0.45, 0.246
    lbq, ubq = list(rb["lbq"]), list(rb["ubq"])
    lbq[2], ubq[2] = 0.0, 0.256
    qw = [0, 0, 0, 10, 10, 10] + [5.0 if nm.endswith("hip_roll") else 1.0 for nm in rb["names"][6:]]
    Qd = np.array(qw + [1.0] * n)
    xg = np.array(qg + [0.0] * n)

    def cost(qa, qb, h, u):
        xbar = ca.vertcat((qa + qb) / 2, (qb - qa) / h) - xg
        return h * (0.5 * ca.dot(xbar, Qd * xbar) + 0.5 * 10.0 * ca.dot(u, u))

    return dict(
        name="littledog_step", n=n, m=m, q=rb["q"], v=rb["v"], T=rb["T"], V=rb["V"],
        phi=ca.vertcat(*[f[2] - step(f[0]) for f in feet]), tangents=[f[0:2] for f in feet],
        B=rb["B"], damping=rb["damping"], mu=1.0, N=30, h=None, T_window=(1.0, 4.0),
        q1=q1, qN_fixed=None, qN_box=([g - 0.01 for g in qg], [g + 0.01 for g in qg]),
        v0=[0.0] * n, lbq=lbq, ubq=ubq, lbu=[-ca.inf] * m, ubu=[ca.inf] * m, alpha=300.0, cost=cost,
        guess_q=lambda k, N: [q1[i] + (qg[i] - q1[i]) * k / (N - 1) for i in range(n)],
    )


def build(p):
    n, m, N = p["n"], p["m"], p["N"]
    q, v = p["q"], p["v"]
    L = p["T"] - p["V"]
    qa, qb, hs = ca.SX.sym("qa", n), ca.SX.sym("qb", n), ca.SX.sym("h")
    Ld = hs * ca.substitute(L, ca.vertcat(q, v), ca.vertcat((qa + qb) / 2, (qb - qa) / hs))
    D1 = ca.Function("D1", [qa, qb, hs], [ca.gradient(Ld, qa)])
    D2 = ca.Function("D2", [qa, qb, hs], [ca.gradient(Ld, qb)])
    M = ca.Function("M", [q], [ca.hessian(p["T"], v)[0]])
    nc = p["phi"].shape[0]
    nd = 2 * p["tangents"][0].shape[0]
    phi_f = ca.Function("phi", [q], [p["phi"]])
    Nmat = ca.jacobian(p["phi"], q)
    Prows = []
    for t in p["tangents"]:
        D = ca.jacobian(t, q)
        Prows.append(ca.vertcat(D, -D))
    J_f = ca.Function("J", [q], [ca.vertcat(Nmat, *Prows)])  # rows: normals (nc), then per contact nd
    P_f = [ca.Function(f"P{i}", [q], [Prows[i]]) for i in range(nc)]
    B = p["B"]

    Q = [ca.SX.sym(f"q{k}", n) for k in range(N)]
    v0 = ca.SX.sym("v0", n)
    U = [ca.SX.sym(f"u{k}", m) for k in range(N - 1)]
    C = [ca.SX.sym(f"c{k}", nc) for k in range(N - 1)]
    Bt = [ca.SX.sym(f"b{k}", nc * nd) for k in range(N - 1)]
    Psi = [ca.SX.sym(f"psi{k}", nc) for k in range(N - 1)]
    Eta = [ca.SX.sym(f"eta{k}", nc * nd) for k in range(N - 1)]
    S = [ca.SX.sym(f"s{k}") for k in range(N - 1)]
    # Extension 1: free equal steps are variables; otherwise h is a constant.
    free_h = p.get("T_window") is not None
    Hs = [ca.SX.sym(f"h{k}") for k in range(N - 1)] if free_h else None
    hk = (lambda k: Hs[k]) if free_h else (lambda k: p["h"])
    damping = p.get("damping")

    def Fd(k):
        f = hk(k) * (B @ U[k]) if m > 0 else ca.SX.zeros(n)
        if damping is not None and np.any(damping):  # extension 2
            f = f - damping * (Q[k + 1] - Q[k])
        return f

    def contact_impulse(k):
        lam = ca.vertcat(C[k], Bt[k])
        return J_f(Q[k + 1]).T @ lam

    geq, gin = [], []
    geq.append(M(Q[0]) @ v0 + D1(Q[0], Q[1], hk(0)) + 0.5 * Fd(0) + contact_impulse(0))
    for k in range(1, N - 1):
        geq.append(D2(Q[k - 1], Q[k], hk(k - 1)) + D1(Q[k], Q[k + 1], hk(k)) + 0.5 * Fd(k - 1) + 0.5 * Fd(k) + contact_impulse(k))
    for k in range(N - 1):
        for i in range(nc):
            beta = Bt[k][i * nd:(i + 1) * nd]
            eta = Eta[k][i * nd:(i + 1) * nd]
            geq.append(P_f[i](Q[k + 1]) @ (Q[k + 1] - Q[k]) / hk(k) + Psi[k][i] * np.ones(nd) - eta)
    for k in range(N - 1):
        ph = phi_f(Q[k + 1])
        cone = [p["mu"] * C[k][i] - ca.sum1(Bt[k][i * nd:(i + 1) * nd]) for i in range(nc)]
        gin.append(ph)
        gin.append(ca.vertcat(*cone))
        gin.append(S[k] - ca.dot(Eta[k], Bt[k]))
        gin.append(S[k] - ca.dot(C[k], ph))
        gin.append(S[k] - sum(Psi[k][i] * cone[i] for i in range(nc)))
    geq = ca.vertcat(*geq)
    gin = ca.vertcat(*gin)
    # The equal-step rows follow all per-interval rows.
    gstep = ca.vertcat(*[Hs[k] - Hs[k + 1] for k in range(N - 2)]) if free_h else ca.SX.zeros(0)

    cost = p["alpha"] * sum(S)
    if p.get("cost") is not None:
        for k in range(N - 1):
            cost += p["cost"](Q[k], Q[k + 1], hk(k), U[k])
    elif p["Q"] is not None:
        h = p["h"]
        qt = np.array(p["q_target"])
        for k in range(N - 1):
            qbar = (Q[k] + Q[k + 1]) / 2
            cost += h * (0.5 * (qbar - qt).T @ p["Q"] @ (qbar - qt) + 0.5 * U[k].T @ p["R"] @ U[k])

    xs, lbx, ubx, x0 = [], [], [], []

    def add(var, lb, ub, guess):
        xs.append(var)
        lbx.extend(lb)
        ubx.extend(ub)
        x0.extend(guess)

    for k in range(N):
        lb, ub = list(p["lbq"]), list(p["ubq"])
        if k == 0:
            lb = ub = list(p["q1"])
        if k == N - 1 and p["qN_fixed"] is not None:
            lb = ub = list(p["qN_fixed"])
        if k == N - 1 and p.get("qN_box") is not None:
            lb, ub = list(p["qN_box"][0]), list(p["qN_box"][1])
        guess = p["guess_q"](k, N)
        if k == 0:
            guess = list(p["q1"])
        add(Q[k], lb, ub, guess)
    add(v0, p["v0"], p["v0"], p["v0"])
    for k in range(N - 1):
        add(U[k], p["lbu"], p["ubu"], [0.0] * m)
        add(C[k], [0.0] * nc, [ca.inf] * nc, [0.01] * nc)
        add(Bt[k], [0.0] * (nc * nd), [ca.inf] * (nc * nd), [0.01] * (nc * nd))
        add(Psi[k], [0.0] * nc, [ca.inf] * nc, [0.01] * nc)
        add(Eta[k], [0.0] * (nc * nd), [ca.inf] * (nc * nd), [0.01] * (nc * nd))
        add(S[k], [0.0], [ca.inf], [0.01])
        if free_h:
            tmin, tmax = p["T_window"]
            add(Hs[k], [tmin / (N - 1)], [tmax / (N - 1)], [tmax / (N - 1)])
    X = ca.vertcat(*xs)
    g = ca.vertcat(geq, gin, gstep)
    lbg = [0.0] * geq.shape[0] + [0.0] * gin.shape[0] + [0.0] * gstep.shape[0]
    ubg = [0.0] * geq.shape[0] + [ca.inf] * gin.shape[0] + [0.0] * gstep.shape[0]
    return dict(X=X, f=cost, g=g, lbg=lbg, ubg=ubg, lbx=lbx, ubx=ubx, x0=x0,
                Q=Q, U=U, C=C, Bt=Bt, S=S, n_eq=geq.shape[0], nc=nc, nd=nd)


def initial_values(nlp):
    f = ca.Function("fg", [nlp["X"]], [nlp["f"], nlp["g"]])
    fv, gv = f(nlp["x0"])
    gv = np.array(gv).ravel()
    lbg, ubg = np.array(nlp["lbg"]), np.array(nlp["ubg"])
    viol = np.maximum(np.maximum(lbg - gv, gv - ubg), 0.0)
    x0, lbx, ubx = np.array(nlp["x0"]), np.array(nlp["lbx"]), np.array(nlp["ubx"])
    bviol = np.maximum(np.maximum(lbx - x0, x0 - ubx), 0.0)
    return dict(objective=float(fv), max_constraint_violation=float(max(viol.max(), bviol.max())),
                equality_residual_norm=float(np.linalg.norm(gv[: nlp["n_eq"]])))


OPTIONS = {"ipopt.tol": 1e-6, "ipopt.linear_solver": "mumps", "ipopt.max_iter": 3000,
           "ipopt.mu_strategy": "adaptive", "ipopt.print_level": 0, "print_time": False}


def bench(p):
    """One solve, timed as vito bench times its own: the solver call only (building the
    expressions is not counted), split into CasADi's function evaluations and the rest."""
    nlp = build(p)
    solver = ca.nlpsol("s", "ipopt", {"x": nlp["X"], "f": nlp["f"], "g": nlp["g"]}, OPTIONS)
    start = time.perf_counter()
    res = solver(x0=nlp["x0"], lbx=nlp["lbx"], ubx=nlp["ubx"], lbg=nlp["lbg"], ubg=nlp["ubg"])
    wall = time.perf_counter() - start
    stats = solver.stats()
    functions = sum(v for k, v in stats.items() if k.startswith("t_wall_nlp_"))
    slack = np.array(ca.Function("s", [nlp["X"]], [ca.vertcat(*nlp["S"])])(res["x"])).ravel()
    return dict(problem=p["name"].replace("_", "-"), implementation="CasADi %s SX, bundled Ipopt" % ca.__version__,
                variables=int(nlp["X"].shape[0]), constraints=len(nlp["lbg"]),
                status=stats["return_status"], iterations=int(stats["iter_count"]),
                objective=float(res["f"]), max_slack=float(slack.max()),
                wall_s=wall, functions_s=functions, ipopt_s=wall - functions)


def solve(p):
    nlp = build(p)
    init = initial_values(nlp)
    solver = ca.nlpsol("s", "ipopt", {"x": nlp["X"], "f": nlp["f"], "g": nlp["g"]}, OPTIONS)
    res = solver(x0=nlp["x0"], lbx=nlp["lbx"], ubx=nlp["ubx"], lbg=nlp["lbg"], ubg=nlp["ubg"])
    stats = solver.stats()
    xopt = np.array(res["x"]).ravel()
    ev = ca.Function("ev", [nlp["X"]], [ca.horzcat(*nlp["Q"]).T, ca.vertcat(*nlp["S"]),
                                         ca.horzcat(*nlp["C"]).T, ca.horzcat(*nlp["Bt"]).T]
                     + ([ca.horzcat(*nlp["U"]).T] if p["m"] > 0 else []))
    outs = ev(xopt)
    qtraj = np.array(outs[0])
    slack = np.array(outs[1]).ravel()
    normal = np.array(outs[2])
    beta = np.array(outs[3])
    nc, nd = nlp["nc"], nlp["nd"]
    half = nd // 2
    net_friction = [[[float(beta[k, i * nd + j] - beta[k, i * nd + j + half]) for j in range(half)]
                     for i in range(nc)] for k in range(beta.shape[0])]
    out = dict(
        problem=p["name"], implementation="CasADi %s + its bundled Ipopt (MUMPS), SX symbolic derivatives" % ca.__version__,
        status=stats["return_status"], iterations=int(stats["iter_count"]),
        objective=float(res["f"]), max_slack=float(slack.max()), initial_guess=init,
        q=qtraj.tolist(), normal_impulse=normal.tolist(), net_friction=net_friction,
    )
    if p["m"] > 0:
        out["u"] = np.array(outs[4]).tolist()
    return out


PROBLEMS = {"hopper-2d": hopper, "brick-3d": brick, "spring-flamingo-walk": spring_flamingo,
            "littledog-step": littledog}


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("--bench", "--initial"):
        unknown = [name for name in sys.argv[2:] if name not in PROBLEMS]
        if unknown:
            sys.exit("unknown problem %s (known: %s)" % (", ".join(unknown), ", ".join(PROBLEMS)))
        for name in sys.argv[2:] or PROBLEMS:
            p = PROBLEMS[name]()
            row = bench(p) if sys.argv[1] == "--bench" else dict(problem=name, **initial_values(build(p)))
            print(json.dumps(row), flush=True)
        return
    outdir = sys.argv[1] if len(sys.argv) > 1 else "."
    for prob in (hopper(), brick()):
        out = solve(prob)
        path = f"{outdir}/{prob['name']}.json"
        with open(path + ".tmp", "w") as fh:
            json.dump(out, fh, indent=1)
        import os
        os.replace(path + ".tmp", path)
        print(prob["name"], out["status"], out["iterations"], "objective %.10f" % out["objective"],
              "max slack %.2e" % out["max_slack"], "init", out["initial_guess"])


if __name__ == "__main__":
    main()
