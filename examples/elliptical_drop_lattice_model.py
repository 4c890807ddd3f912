#!/usr/bin/env python3
"""The elliptical drop as the weakly compressible schemes see it on an affinely stretched lattice.

The exact flow maps the initial lattice x = n dx (n integer) to x = diag(a) n dx. On that lattice,
for the linear velocity u_i = A_i x_i and the quadratic pressure of the exact solution, the
continuity and momentum sums of Fang 2006 (eqs. 26-27; Ren 2015 eqs. 13-14) read, away from the
surface, exactly

    div u  ->  sum_a M_aa A_a,        grad p  ->  M grad p,
    M = sum_j V_j (-(1/r) dW/dr) x_ij x_ij^T     (continuum value: the identity),

a function of the stretch a and of h/dx only (`viscosph::scene::elliptical_drop::gradient_moment`).
With a stiff equation of state the discrete divergence stays 0, so the drop follows

    da_a/dt = A_a a_a,      dA_a/dt = -A_a^2 + M_aa C / a_a^2,
    C = (sum_a M_aa A_a^2 - sum_a (dM_aa/dt) A_a) / sum_a (M_aa^2 / a_a^2),

which is the exact ODE (the scene's page) when M = I. This script integrates both with the cubic
spline (the weakly compressible schemes' kernel) and prints the semi-axes' relative error,
the volume prod(a) and M along the way: the error that the drop keeps at any resolution for a
given h/dx.

usage: elliptical_drop_lattice_model.py [N=3] [h/dx=1.5] [t_end=0.008]
"""
import itertools
import math
import sys

A0 = 100.0  # initial stretching rate [1/s]: u = A0 (-x, y, 0)


def cubic_dfdq(q):
    """d/dq of the cubic spline's shape 1 - 3/2 q^2 + 3/4 q^3 (q < 1), (2 - q)^3 / 4 (q < 2)."""
    if q < 1.0:
        return -3.0 * q + 2.25 * q * q
    if q < 2.0:
        return -0.75 * (2.0 - q) ** 2
    return 0.0


def moment(n_dim, ratio, a):
    """Diagonal of M on the lattice diag(a) n (dx = 1, volumes 1), cubic spline, h = ratio."""
    sigma = {2: 10.0 / (7.0 * math.pi), 3: 1.0 / math.pi}[n_dim]
    reach = [int(2.0 * ratio / a[k]) + 1 for k in range(n_dim)]
    m = [0.0] * n_dim
    for n in itertools.product(*[range(-r, r + 1) for r in reach]):
        r = math.sqrt(sum((a[i] * n[i]) ** 2 for i in range(n_dim)))
        if r == 0.0 or r >= 2.0 * ratio:
            continue
        w = -sigma * cubic_dfdq(r / ratio) / (ratio ** (n_dim + 1) * r)
        for i in range(n_dim):
            m[i] += w * (a[i] * n[i]) ** 2
    return m


def rates(n_dim, ratio, y):
    """d(a, A)/dt; ratio None: the exact ODE (M = I)."""
    a, A = y[:n_dim], y[n_dim:]
    if ratio is None:
        m, mdot = [1.0] * n_dim, [0.0] * n_dim
    else:
        m = moment(n_dim, ratio, a)
        eps = 1e-6
        ad = [A[i] * a[i] for i in range(n_dim)]
        mp = moment(n_dim, ratio, [a[i] + eps * ad[i] for i in range(n_dim)])
        mm = moment(n_dim, ratio, [a[i] - eps * ad[i] for i in range(n_dim)])
        mdot = [(mp[i] - mm[i]) / (2.0 * eps) for i in range(n_dim)]
    c = (sum(m[i] * A[i] ** 2 for i in range(n_dim)) - sum(mdot[i] * A[i] for i in range(n_dim))) / sum(
        m[i] ** 2 / a[i] ** 2 for i in range(n_dim)
    )
    return [A[i] * a[i] for i in range(n_dim)] + [-A[i] ** 2 + m[i] * c / a[i] ** 2 for i in range(n_dim)]


def rk4(f, y, h):
    k1 = f(y)
    k2 = f([y[i] + 0.5 * h * k1[i] for i in range(len(y))])
    k3 = f([y[i] + 0.5 * h * k2[i] for i in range(len(y))])
    k4 = f([y[i] + h * k3[i] for i in range(len(y))])
    return [y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(len(y))]


def main():
    n_dim = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    ratio = float(sys.argv[2]) if len(sys.argv) > 2 else 1.5
    t_end = float(sys.argv[3]) if len(sys.argv) > 3 else 0.008
    y0 = [1.0] * n_dim + [-A0, A0] + [0.0] * (n_dim - 2)
    steps, prints = 400, 8
    h = t_end / steps
    model, exact = list(y0), list(y0)
    print(f"{n_dim}D, cubic spline, h = {ratio} dx; M on the initial lattice: "
          + ", ".join(f"{m:.4f}" for m in moment(n_dim, ratio, [1.0] * n_dim)))
    for k in range(1, steps + 1):
        model = rk4(lambda y: rates(n_dim, ratio, y), model, h)
        exact = rk4(lambda y: rates(n_dim, None, y), exact, h)
        if k % (steps // prints) == 0:
            a, e = model[:n_dim], exact[:n_dim]
            err = ", ".join(f"{100.0 * (a[i] / e[i] - 1.0):+.3f}" for i in range(n_dim))
            m = ", ".join(f"{x:.4f}" for x in moment(n_dim, ratio, a))
            print(f"t = {k * h:.4f} s: exact semi-axes {', '.join(f'{x:.4f}' for x in e)}; "
                  f"error {err} %; volume {math.prod(a):.4f}; M {m}")


if __name__ == "__main__":
    main()
