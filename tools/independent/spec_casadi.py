#!/usr/bin/env python3
"""Independent implementation of SPEC.md's reference problems (hopper-2d, brick-3d).

It shares no code with vito: closed-form energies straight from SPEC.md, symbolic
derivatives by CasADi, and CasADi's own bundled Ipopt. Its results, stored in
tests/data/independent/*.json, are what vito's objective and trajectories are compared
against (tests/independent.rs). Regenerate with:

    pip install casadi==3.8.2
    python3 tools/independent/spec_casadi.py tests/data/independent

The NLP follows SPEC.md "Common formulation" line by line.
"""
import json
import sys

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


def brick():
    n, m = 6, 0
    q = ca.SX.sym("q", n)
    v = ca.SX.sym("v", n)
    a, b, c, mass = 0.2, 0.1, 0.05, 1.0
    R = rot("z", q[5]) @ rot("y", q[4]) @ rot("x", q[3])
    Rdot = ca.SX.zeros(3, 3)
    for i in range(3):
        for j in range(3):
            Rdot[i, j] = ca.jtimes(R[i, j], q, v)
    W = R.T @ Rdot
    omega = ca.vertcat(W[2, 1], W[0, 2], W[1, 0])
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


def build(p):
    n, m, N, h = p["n"], p["m"], p["N"], p["h"]
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

    def Fd(k):
        return h * (B @ U[k]) if m > 0 else ca.SX.zeros(n)

    def contact_impulse(k):
        lam = ca.vertcat(C[k], Bt[k])
        return J_f(Q[k + 1]).T @ lam

    geq, gin = [], []
    geq.append(M(Q[0]) @ v0 + D1(Q[0], Q[1], h) + 0.5 * Fd(0) + contact_impulse(0))
    for k in range(1, N - 1):
        geq.append(D2(Q[k - 1], Q[k], h) + D1(Q[k], Q[k + 1], h) + 0.5 * Fd(k - 1) + 0.5 * Fd(k) + contact_impulse(k))
    for k in range(N - 1):
        for i in range(nc):
            beta = Bt[k][i * nd:(i + 1) * nd]
            eta = Eta[k][i * nd:(i + 1) * nd]
            geq.append(P_f[i](Q[k + 1]) @ (Q[k + 1] - Q[k]) / h + Psi[k][i] * np.ones(nd) - eta)
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

    cost = p["alpha"] * sum(S)
    if p["Q"] is not None:
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
    X = ca.vertcat(*xs)
    g = ca.vertcat(geq, gin)
    lbg = [0.0] * geq.shape[0] + [0.0] * gin.shape[0]
    ubg = [0.0] * geq.shape[0] + [ca.inf] * gin.shape[0]
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


def solve(p):
    nlp = build(p)
    init = initial_values(nlp)
    opts = {"ipopt.tol": 1e-6, "ipopt.linear_solver": "mumps", "ipopt.max_iter": 3000,
            "ipopt.mu_strategy": "adaptive", "ipopt.print_level": 0, "print_time": False}
    solver = ca.nlpsol("s", "ipopt", {"x": nlp["X"], "f": nlp["f"], "g": nlp["g"]}, opts)
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


def main():
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
