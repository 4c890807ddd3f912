"""Steady Oldroyd-B flow in King & Lind's cell by DEVSS-G finite elements.

Unknowns: velocity u (P2), pressure p (P1), polymer stress tau (P1, components xx, xy, yy) and
the projected velocity gradient G (P1, G_ij ~ du_i/dx_j), on the isoparametric meshes of
stokes_fem.py, periodic along x by the same identification of degrees of freedom.

    momentum    (tau + eta_s (L + L^T) + a (L + L^T - G - G^T) - p I) : grad v = rho g . v
    mass        q div u = 0
    projection  (G - L) : H = 0                                 (L = grad u, DEVSS-G)
    Oldroyd-B   (tau + lam (u . grad tau - G tau - tau G^T) - eta_p (G + G^T))
                : (S + c t_s lam u . grad S) = 0

with a = eta_p (the DEVSS-G stabilisation: Guenette & Fortin 1995; Liu, Bornside, Armstrong &
Brown 1998), creeping flow. The SUPG weight t_s = (1 + (2 lam |u| / h)^2)^(-1/2) is there
(c = OldroydB.supg) but off by default (c = 0, Galerkin): with it Newton reaches larger lam on
coarse meshes, but its O(h) perturbation kept the drag from converging over levels 0-2 at
lam = 0.2 s, while the Galerkin drag converges at order 3. The steady equations are solved by
Newton's method (exact Jacobian, checked against finite differences) with continuation in lam
from the Newtonian solution. The drag is the reaction of the discrete momentum equation at the
cylinder, as in stokes_fem.py. PyPI pypardiso, when installed, solves the linear systems.

    python oldroyd_b_fem.py 4    # levels 0-3, lam up to 0.8 s; about 1.5 h
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import stokes_fem as sf

try:  # Intel MKL PARDISO (PyPI pypardiso) factorises these systems 3-5 times faster than SuperLU
    from pypardiso import spsolve as _pardiso
except ImportError:  # pragma: no cover - SuperLU only
    _pardiso = None


def lin_solve(A, b):
    """Solve A x = b. PARDISO's default pivoting (perturbed small pivots) can return a wrong
    solution for these saddle-point Jacobians (relative residual 3.6 on level 3): its answer is
    kept only if the residual is small, SuperLU solves otherwise."""
    if _pardiso is not None:
        x = _pardiso(A.tocsr(), b)
        if np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b):
            return x
    return spla.splu(A.tocsc()).solve(b)


def _t(x):
    """2x2 symmetric tensor field from its (xx, xy, yy) components."""
    return np.array([[x[0], x[1]], [x[1], x[2]]])


def _g(x):
    """2x2 tensor field from its (xx, xy, yx, yy) components."""
    return np.array([[x[0], x[1]], [x[2], x[3]]])


def _mm(a, b):
    return np.einsum("ik...,kj...->ij...", a, b)


def _dd(a, b):
    return np.einsum("ij...,ij...->...", a, b)


def _adv(u, gt):
    """u . grad tau for a tensor given by the gradients of its components gt (3, 2, ...)."""
    return _t(np.einsum("cj...,j...->c...", gt, u))


class OldroydB:
    def __init__(self, geo, rho, eta_s, eta_p, g, level, h_max=sf.H_MAX0):
        self.h_max = h_max
        self.supg = 0.0  # scale of the SUPG weight (0: Galerkin; see the module doc)
        from skfem import Basis, ElementTriP1, ElementTriP2, ElementVector

        self.geo, self.rho, self.eta_s, self.eta_p, self.g = geo, rho, eta_s, eta_p, g
        self.level = level
        m = sf.build_mesh(geo, level, h_max=h_max)
        self.mesh = m
        self.ub = Basis(m, ElementVector(ElementTriP2()), intorder=4)
        self.pb = self.ub.with_element(ElementTriP1())
        self.tb = self.ub.with_element(ElementVector(ElementTriP1(), 3))
        self.gb = self.ub.with_element(ElementVector(ElementTriP1(), 4))
        self.bases = [self.ub, self.pb, self.tb, self.gb]
        sizes = [b.N for b in self.bases]
        self.off = np.concatenate([[0], np.cumsum(sizes)])
        self.n = int(self.off[-1])
        self._periodic()
        self._dirichlet()
        self.x = np.zeros(self.n)

    # ---- dof bookkeeping ----------------------------------------------------------------

    def _periodic(self):
        geo = self.geo
        master = np.arange(self.n)
        if geo.kind == "periodic":
            tol = 1e-8 * geo.H
            for b, off in zip(self.bases, self.off[:-1]):
                for idx in b.split_indices():
                    loc = b.doflocs[:, idx]
                    left = idx[np.abs(loc[0] - geo.x0) < tol]
                    right = idx[np.abs(loc[0] - geo.x0 - geo.L) < tol]
                    yl, yr = b.doflocs[1, left], b.doflocs[1, right]
                    ol, orr = np.argsort(yl), np.argsort(yr)
                    assert len(left) == len(right)
                    assert np.max(np.abs(yl[ol] - yr[orr]), initial=0.0) < tol
                    master[right[orr] + off] = left[ol] + off
        self.keep, self.red = np.unique(master, return_inverse=True)
        n, m = self.n, len(self.keep)
        self.P = sp.csr_matrix((np.ones(n), (np.arange(n), self.red)), shape=(n, m))

    def _dirichlet(self):
        fixed = self.ub.get_dofs(["bottom", "top", "cylinder"]).all()
        fixed = np.append(fixed, self.off[1])  # one pressure value
        D = np.unique(self.red[fixed])
        self.free = np.setdiff1d(np.arange(len(self.keep)), D)

    def split(self, x):
        return [x[self.off[k] : self.off[k + 1]] for k in range(4)]

    # ---- initial guess ----------------------------------------------------------------------

    def newtonian_start(self):
        """u, p of the Newtonian (eta_s + eta_p) Stokes solution on the same mesh; G its
        projected velocity gradient and tau = eta_p (G + G^T), the lam = 0 solution."""
        from skfem import BilinearForm, LinearForm, asm
        from skfem.helpers import grad

        (s,) = sf.solve(
            self.geo,
            sf.Physics(rho=self.rho, eta=self.eta_s + self.eta_p, g=self.g),
            self.level,
            h_max=self.h_max,
        )
        assert s.ub.N == self.ub.N

        @BilinearForm
        def mass(u, v, w):
            return np.einsum("i...,i...->...", u, v)

        @LinearForm
        def rhs_g(v, w):
            gu = grad(w.uu)
            return gu[0, 0] * v[0] + gu[0, 1] * v[1] + gu[1, 0] * v[2] + gu[1, 1] * v[3]

        uu = self.ub.interpolate(s.u)
        G = spla.spsolve(asm(mass, self.gb).tocsc(), asm(rhs_g, self.gb, uu=uu))
        Gq = self.gb.interpolate(G)

        @LinearForm
        def rhs_t(v, w):
            Gm = _g(w.GG)
            return self.eta_p * _dd(Gm + np.swapaxes(Gm, 0, 1), _t(v))

        T = spla.spsolve(asm(mass, self.tb).tocsc(), asm(rhs_t, self.tb, GG=Gq))
        x = np.concatenate([s.x, T, G])
        counts = np.asarray(self.P.sum(axis=0)).ravel()
        self.x = self.P @ (self.P.T @ x / counts)  # periodic copies averaged
        return self.x

    # ---- residual and Jacobian --------------------------------------------------------------

    def _fields(self, x):
        u, p, t, G = self.split(x)
        return dict(
            uu=self.ub.interpolate(u),
            pp=self.pb.interpolate(p),
            tt=self.tb.interpolate(t),
            GG=self.gb.interpolate(G),
        )

    def residual_jacobian(self, x, lam, jac=True):
        from skfem import BilinearForm, LinearForm, asm
        from skfem.helpers import grad

        eta_s, eta_p, a, rho, g = self.eta_s, self.eta_p, self.eta_p, self.rho, self.g
        f = self._fields(x)

        def ts(w):
            un = np.sqrt(w.uu[0] ** 2 + w.uu[1] ** 2)
            return self.supg / np.sqrt(1.0 + (2.0 * lam * un / w.h) ** 2)

        def cres(w):
            """the Oldroyd-B residual at the quadrature points (2x2)"""
            T, Gm = _t(w.tt), _g(w.GG)
            return (
                T
                + lam * (_adv(w.uu, grad(w.tt)) - _mm(Gm, T) - _mm(T, np.swapaxes(Gm, 0, 1)))
                - eta_p * (Gm + np.swapaxes(Gm, 0, 1))
            )

        # residuals ------------------------------------------------------------------
        @LinearForm
        def r_mom(v, w):
            Lu = grad(w.uu)
            Gm = _g(w.GG)
            s = (
                _t(w.tt)
                + (eta_s + a) * (Lu + np.swapaxes(Lu, 0, 1))
                - a * (Gm + np.swapaxes(Gm, 0, 1))
            )
            return _dd(s, grad(v)) - w.pp * (grad(v)[0, 0] + grad(v)[1, 1]) - rho * g * v[0]

        @LinearForm
        def r_mass(q, w):
            Lu = grad(w.uu)
            return -(Lu[0, 0] + Lu[1, 1]) * q

        @LinearForm
        def r_proj(H, w):
            return _dd(_g(w.GG) - grad(w.uu), _g(H))

        @LinearForm
        def r_const(S, w):
            St = _t(S)
            test = St + ts(w) * lam * _adv(w.uu, grad(S))
            return _dd(cres(w), test)

        R = np.concatenate(
            [
                asm(r_mom, self.ub, **f),
                asm(r_mass, self.pb, **f),
                asm(r_const, self.tb, **f),
                asm(r_proj, self.gb, **f),
            ]
        )
        if not jac:
            return R, None

        # Jacobian blocks J[test][trial] ----------------------------------------------
        def sym(A):
            return A + np.swapaxes(A, 0, 1)

        @BilinearForm
        def m_u(du, v, w):
            return (eta_s + a) * _dd(sym(grad(du)), grad(v))

        @BilinearForm
        def m_p(dp, v, w):
            return -dp * (grad(v)[0, 0] + grad(v)[1, 1])

        @BilinearForm
        def m_t(dt, v, w):
            return _dd(_t(dt), grad(v))

        @BilinearForm
        def m_g(dG, v, w):
            return -a * _dd(sym(_g(dG)), grad(v))

        @BilinearForm
        def c_u(du, q, w):
            return -(grad(du)[0, 0] + grad(du)[1, 1]) * q

        @BilinearForm
        def g_u(du, H, w):
            return -_dd(grad(du), _g(H))

        @BilinearForm
        def g_g(dG, H, w):
            return _dd(_g(dG), _g(H))

        def test(S, w):
            return _t(S) + ts(w) * lam * _adv(w.uu, grad(S))

        @BilinearForm
        def s_t(dt, S, w):
            T = _t(dt)
            Gm = _g(w.GG)
            d = T + lam * (_adv(w.uu, grad(dt)) - _mm(Gm, T) - _mm(T, np.swapaxes(Gm, 0, 1)))
            return _dd(d, test(S, w))

        @BilinearForm
        def s_u(du, S, w):
            # d/du of the residual and of the SUPG test function, with
            # d t_s = -t_s^3 (2 lam / h)^2 (u . du)
            d = lam * _adv(du, grad(w.tt))
            t = ts(w)
            dts = (
                -(t**3)
                / self.supg**2
                * (2.0 * lam / w.h) ** 2
                * (w.uu[0] * du[0] + w.uu[1] * du[1])
                if self.supg
                else 0.0 * t
            )
            dtest = t * lam * _adv(du, grad(S)) + dts * lam * _adv(w.uu, grad(S))
            return _dd(d, test(S, w)) + _dd(cres(w), dtest)

        @BilinearForm
        def s_g(dG, S, w):
            T, dGm = _t(w.tt), _g(dG)
            d = -lam * (_mm(dGm, T) + _mm(T, np.swapaxes(dGm, 0, 1))) - eta_p * sym(dGm)
            return _dd(d, test(S, w))

        ub, pb, tb, gb = self.bases
        J = sp.bmat(
            [
                [
                    asm(m_u, ub, **f),
                    asm(m_p, pb, ub, **f),
                    asm(m_t, tb, ub, **f),
                    asm(m_g, gb, ub, **f),
                ],
                [asm(c_u, ub, pb, **f), None, None, None],
                [asm(s_u, ub, tb, **f), None, asm(s_t, tb, tb, **f), asm(s_g, gb, tb, **f)],
                [asm(g_u, ub, gb, **f), None, None, asm(g_g, gb, gb, **f)],
            ],
            format="csr",
        )
        return R, J

    def newton(self, lam, tol=1e-10, maxit=12, verbose=False):
        """Newton's method from the current state; raises RuntimeError when it does not
        converge in maxit steps or the residual grows a hundredfold (divergence)."""
        P, free = self.P, self.free
        x = self.x.copy()
        r0 = None
        for it in range(1, maxit + 1):
            R, J = self.residual_jacobian(x, lam)
            Rr = P.T @ R
            rnorm = np.linalg.norm(Rr[free])
            r0 = rnorm if r0 is None else r0
            if rnorm > 100.0 * r0 or not np.isfinite(rnorm):
                break
            Jr = (P.T @ J @ P).tocsr()
            dx = np.zeros(P.shape[1])
            dx[free] = lin_solve(Jr[free][:, free], -Rr[free])
            x = x + P @ dx
            rel = np.linalg.norm((P @ dx)[: self.off[1]]) / np.linalg.norm(x[: self.off[1]])
            if verbose:
                print(f"      Newton {it}: |du|/|u| = {rel:.2e}, |R| = {rnorm:.2e}")
            if rel < tol:
                self.x = x
                return it
        raise RuntimeError(f"Newton did not converge at lambda = {lam}")

    def forces(self, lam):
        """Drag and lift on the cylinder (reactions), flow rate, <u>."""
        R, _ = self.residual_jacobian(self.x, lam, jac=False)
        r = -R[: self.off[1]]
        d = self.ub.get_dofs(["cylinder"]).all()
        ix, iy = self.ub.split_indices()
        Fx = float(r[np.intersect1d(d, ix)].sum())
        Fy = float(r[np.intersect1d(d, iy)].sum())
        _, umean, Q = sf.flow_measures(self.ub, self.x[: self.off[1]])
        eta0 = self.eta_s + self.eta_p
        Fpd = Fx + self.rho * self.g * math.pi * self.geo.R**2
        return dict(
            drag=Fx,
            lift=Fy,
            flow_rate=Q,
            u_mean_fluid=umean,
            u_bulk=Q / self.geo.H,
            K_fluid=Fx / (eta0 * umean),
            K_pd=Fpd / (eta0 * Q / self.geo.H),
        )


def evaluate(basis, vec, pts):
    """Values (ncomp x N) of a finite element field at points, as stokes_fem.evaluate."""
    from skfem import MeshTri1

    m1 = MeshTri1(basis.mesh.p, basis.mesh.t)
    cells = m1.element_finder()(*pts)
    X = basis.mapping.invF(pts[:, :, None], tind=cells)
    out = 0.0
    for k in range(basis.Nbfun):
        phi = basis.elem.gbasis(basis.mapping, X, k, tind=cells)[0].value
        phi = phi[..., 0] if phi.ndim == 3 else phi[None, :, 0]
        out = out + phi * vec[basis.element_dofs[k, cells]]
    return np.atleast_2d(out)


KL_LAMBDA = (0.2, 0.6, 0.8)  # [s]: King & Lind's Wi = <u> lam / R with <u> ~ 1 m/s (Fig. 10)
LAMBDA_STEP = 0.1


def sweep(model, targets=KL_LAMBDA, step=LAMBDA_STEP, verbose=False):
    """Newton continuation in lam from the Newtonian solution, in steps of `step`; returns
    {lam: (forces, state)} for the targets reached before Newton first fails."""
    model.newtonian_start()
    out, lam = {}, 0.0
    while lam < max(targets) - 1e-12:
        lam = round(lam + step, 10)
        try:
            steps = model.newton(lam, verbose=verbose)
        except RuntimeError:
            break
        if any(abs(lam - t) < 1e-9 for t in targets):
            r = model.forces(lam)
            r.update(lam=lam, Wi=lam * r["u_mean_fluid"] / model.geo.R, newton=steps)
            out[lam] = (r, model.x.copy())
    return out


def study_kl(out, levels=4, verbose=True):
    """King & Lind's cell, Oldroyd-B beta = 0.59, lam = 0.2, 0.6, 0.8 s, Galerkin, on nested
    meshes: convergence table (oldroyd_b_convergence.csv) and the centre-line profiles of the
    finest level that reached each lam (oldroyd_b_centreline.csv)."""
    kl = sf.KL
    eta0 = kl["eta0"]
    rows, finest = [], {}
    for lev in range(levels):
        t0 = time.perf_counter()
        model = OldroydB(sf.kl_geometry(), kl["rho"], 0.59 * eta0, 0.41 * eta0, kl["g"], lev)
        res = sweep(model)
        for lam in KL_LAMBDA:
            if lam not in res:
                if verbose:
                    print(f"  Oldroyd-B level {lev} lam {lam}: Newton fails", flush=True)
                continue
            r = res[lam][0]
            r.update(level=lev, unknowns=len(model.free))
            rows.append(r)
            finest[lam] = (model, res[lam])
            if verbose:
                print(
                    f"  Oldroyd-B level {lev} lam {lam}: Wi {r['Wi']:.6f}, drag "
                    f"{r['drag']:.8g} N/m, <u> {r['u_mean_fluid']:.8g} m/s, K "
                    f"{r['K_fluid']:.8g}, lift {r['lift']:.2e} ({time.perf_counter() - t0:.0f} s)",
                    flush=True,
                )
    for lam in KL_LAMBDA:
        sub = [r for r in rows if r["lam"] == lam]
        if len(sub) >= 3:
            sf.add_convergence(sub, ["drag", "u_mean_fluid", "K_fluid"])
        for r in sub:
            for k in ("drag", "u_mean_fluid", "K_fluid"):
                r.setdefault(f"order_{k}", float("nan"))
                r.setdefault(f"error_{k}", float("nan"))
    cols = [
        "lam",
        "level",
        "unknowns",
        "Wi",
        "drag",
        "lift",
        "flow_rate",
        "u_mean_fluid",
        "u_bulk",
        "K_fluid",
        "K_pd",
        "order_drag",
        "error_drag",
        "order_u_mean_fluid",
        "error_u_mean_fluid",
        "order_K_fluid",
        "error_K_fluid",
    ]
    rows.sort(key=lambda r: (r["lam"], r["level"]))
    sf.write_csv(f"{out}/oldroyd_b_convergence.csv", rows, cols)
    prof = {}
    for lam, (model, (r, x)) in sorted(finest.items()):
        s, pts = sf.centreline_points(model.geo)
        prof["s_over_R"] = s / model.geo.R
        um = r["u_mean_fluid"]
        u = evaluate(model.ub, x[: model.off[1]], pts)[0]
        tau = evaluate(model.tb, x[model.off[2] : model.off[3]], pts)
        prof[f"u_over_mean_lam{lam}"] = u / um
        prof[f"tauxx_scaled_lam{lam}"] = tau[0] / (model.eta_s * um / model.geo.R)
    cols = list(prof)
    sf.write_csv(
        f"{out}/oldroyd_b_centreline.csv",
        [{c: float(prof[c][i]) for c in cols} for i in range(len(prof["s_over_R"]))],
        cols,
    )
    return rows


def figure(out):
    """Centre-line u/<u> and tau_xx/(eta_s <u>/R), King & Lind 2021 Fig. 10's axes, for the
    lam reached, with the Newtonian profile."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prof = sf.read_csv(f"{out}/oldroyd_b_centreline.csv")
    newt = sf.read_csv(f"{out}/centreline.csv")
    conv = sf.read_csv(f"{out}/oldroyd_b_convergence.csv")
    s = [p["s_over_R"] for p in prof]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    a1.plot(
        [p["s_over_R"] for p in newt], [p["u_over_mean"] for p in newt], "k:", label="Newtonian"
    )
    for lam, c in zip(KL_LAMBDA, ("k", "r", "b")):
        key = f"u_over_mean_lam{lam}"
        if key not in prof[0]:
            continue
        lev = max(r["level"] for r in conv if r["lam"] == lam)
        wi = [r["Wi"] for r in conv if r["lam"] == lam and r["level"] == lev][0]
        lab = f"lam = {lam} s (Wi = {wi:.3f}), level {lev}"
        a1.plot(s, [p[key] for p in prof], c + "-", label=lab)
        a2.plot(s, [p[f"tauxx_scaled_lam{lam}"] for p in prof], c + "-", label=lab)
    a1.set_xlabel("s / R (0: rear of a cylinder, 4: front of the next)")
    a1.set_ylabel("u / <u> on y = H/2")
    a2.set_xlabel("s / R")
    a2.set_ylabel("tau_p,xx / (eta_s <u> / R) on y = H/2")
    for a in (a1, a2):
        a.set_xlim(0, 4)
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle("Oldroyd-B, beta = 0.59, King & Lind's cell (DEVSS-G Galerkin FEM)", fontsize=10)
    fig.tight_layout()
    path = f"{out}/oldroyd_b.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    import sys

    if len(sys.argv) > 1 and sys.argv[1] == "figure":
        print(figure(sf.HERE))
    else:
        study_kl(sf.HERE, int(sys.argv[1]) if len(sys.argv) > 1 else 4)
        print(figure(sf.HERE))
