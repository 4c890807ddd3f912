"""Finite-element reference for steady Newtonian flow past a cylinder in a channel.

Two geometries, both a channel of height H with no-slip walls at y = 0 and y = H and a
cylinder of radius R on the centre line:

* ``periodic``: King & Lind's periodic array of cylinders (King & Lind 2021, section IV.B;
  the cell of Vazquez-Quesada & Ellero 2012): a cell of length L, periodic along x, driven by
  a uniform body force rho g along x;
* ``channel``: the confined-cylinder benchmark (Alves, Pinho & Oliveira 2001; Hulsen, Fattal
  & Kupferman 2005): a long channel with a fully developed (Poiseuille) profile of mean U
  imposed at the inlet and at the outlet.

Discretisation: Taylor-Hood P2-P1 on an isoparametric (quadratic) triangular mesh, so that the
cylinder is represented to O(h^3); the coarsest mesh comes from gmsh (graded towards the
cylinder, matching nodes on the periodic sides), finer levels by uniform refinement with the new
boundary nodes put back on the circle. Periodicity is imposed by identifying the degrees of
freedom on x = x0 + L with those on x = x0 at the same height (a 0/1 prolongation matrix P, the
reduced system is P^T A P). Steady Navier-Stokes is solved from the Stokes solution by defect
correction with the factorised Stokes operator.

Forces: the drag and lift on the cylinder are the reactions of the discrete momentum equation at
the cylinder's velocity degrees of freedom (the variational or Babuska-Miller form,
F = -(a(u,w) + b(w,p) + c(u;u,w) - (rho g, w)) with w = e_x on the cylinder and 0 on the other
boundaries), which converges at twice the energy-norm order; the stress integrated over the
cylinder surface is reported beside it as a cross-check. The wall force comes the same way, and
the momentum balance rho g A_fluid = F_cylinder + F_walls closes to round-off for Stokes flow.

Run ``python stokes_fem.py --help``; ``python stokes_fem.py all`` writes every CSV and the figure
of this directory (about 14 minutes on one core, 5 GB); ``python stokes_fem.py level 0`` solves
the coarsest level of King & Lind's cell in a fraction of a second (what the CI test does).
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

HERE = os.path.dirname(os.path.abspath(__file__))

# King & Lind 2021, section IV.B, in SI units.
KL = dict(R=1.0, L=6.0, H=4.0, rho=1.0, eta0=41.66, g=300.0)

# Coarsest mesh (level 0) and the number of uniform refinements of the convergence study.
H_CYL0 = 0.25  # element size on the cylinder, in units of R
H_FAR0 = 0.5  # element size one radius away from the cylinder and beyond, in units of R
H_MAX0 = 1.0  # element size from 6 R away from the cylinder on, in units of R (the long cells
# and the channel use 2 R: P2 represents their Poiseuille far field exactly)
LEVELS = 5  # levels 0..LEVELS-1 of King & Lind's cell
CHANNEL_LEVELS = 4  # the 30 R long channel's level 4 would need 1.4e6 unknowns, > 17 GB in SuperLU


# --------------------------------------------------------------------------------------------
# mesh
# --------------------------------------------------------------------------------------------


@dataclass
class Geometry:
    kind: str  # "periodic" or "channel"
    L: float  # cell (or channel) length
    H: float  # channel height, walls at y = 0 and y = H
    R: float  # cylinder radius
    x0: float = 0.0  # left end
    xc: float = None  # cylinder centre x (default: middle of the cell)

    def __post_init__(self):
        if self.xc is None:
            self.xc = self.x0 + 0.5 * self.L

    @property
    def yc(self):
        return 0.5 * self.H

    @property
    def fluid_area(self):
        return self.L * self.H - math.pi * self.R**2


def gmsh_mesh(geo: Geometry, h_cyl: float, h_far: float, h_max: float):
    """Linear triangles (points 2xN, triangles 3xM) from gmsh, graded towards the cylinder.

    For the periodic cell the right side is meshed as a translate of the left side
    (gmsh.model.mesh.setPeriodic), so the nodes of the two sides match pairwise."""
    import gmsh

    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("cell")
        occ = gmsh.model.occ
        rect = occ.addRectangle(geo.x0, 0.0, 0.0, geo.L, geo.H)
        disk = occ.addDisk(geo.xc, geo.yc, 0.0, geo.R, geo.R)
        occ.cut([(2, rect)], [(2, disk)])
        occ.synchronize()
        curves = gmsh.model.getEntities(1)
        left, right, circle = [], [], []
        for _, c in curves:
            xmin, ymin, _, xmax, ymax, _ = gmsh.model.getBoundingBox(1, c)
            eps = 1e-5 * geo.R  # OCC pads bounding boxes
            if xmax - xmin < eps and abs(xmin - geo.x0) < eps:
                left.append(c)
            elif xmax - xmin < eps and abs(xmax - geo.x0 - geo.L) < eps:
                right.append(c)
            elif xmax - xmin < 2.0 * geo.R + eps and ymin > eps and ymax < geo.H - eps:
                circle.append(c)
        assert len(left) == 1 and len(right) == 1 and circle, (left, right, circle)
        if geo.kind == "periodic":
            shift = [1, 0, 0, geo.L, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
            gmsh.model.mesh.setPeriodic(1, right, left, shift)
        f = gmsh.model.mesh.field
        dist = f.add("Distance")
        f.setNumbers(dist, "CurvesList", circle)
        f.setNumber(dist, "Sampling", 400)
        near = f.add("Threshold")
        f.setNumber(near, "InField", dist)
        f.setNumber(near, "SizeMin", h_cyl * geo.R)
        f.setNumber(near, "SizeMax", h_far * geo.R)
        f.setNumber(near, "DistMin", 0.0)
        f.setNumber(near, "DistMax", 1.0 * geo.R)
        far = f.add("Threshold")
        f.setNumber(far, "InField", dist)
        f.setNumber(far, "SizeMin", h_far * geo.R)
        f.setNumber(far, "SizeMax", h_max * geo.R)
        f.setNumber(far, "DistMin", 2.0 * geo.R)
        f.setNumber(far, "DistMax", 6.0 * geo.R)
        both = f.add("Min")
        f.setNumbers(both, "FieldsList", [near, far])
        f.setAsBackgroundMesh(both)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = coords.reshape(-1, 3)
        etypes, _, enodes = gmsh.model.mesh.getElements(2)
        tri = np.asarray(enodes[list(etypes).index(2)], dtype=np.int64).reshape(-1, 3)
    finally:
        gmsh.finalize()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    t = index[tri]
    used = np.unique(t)
    renum = np.full(len(tags), -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    p = xyz[used, :2].T.copy()
    return p, renum[t].T.copy()


def snap_to_circle(x, geo: Geometry):
    """Radially project the points x (2xN) onto the cylinder surface."""
    d = x - np.array([[geo.xc], [geo.yc]])
    return np.array([[geo.xc], [geo.yc]]) + geo.R * d / np.linalg.norm(d, axis=0)


def on_cylinder(x, geo: Geometry):
    """Points (2xN) on or next to the cylinder surface: the walls are a radius away."""
    r = np.hypot(x[0] - geo.xc, x[1] - geo.yc)
    return r < 1.2 * geo.R


def build_mesh(geo: Geometry, level: int, h_cyl=H_CYL0, h_far=H_FAR0, h_max=H_MAX0):
    """Quadratic (isoparametric) mesh of the given refinement level, with named boundaries
    left, right, bottom, top, cylinder: the gmsh mesh split `level` times into four, the new
    cylinder nodes and the mid-side nodes of the cylinder's facets put on the circle."""
    from skfem import MeshTri1, MeshTri2

    p, t = gmsh_mesh(geo, h_cyl, h_far, h_max)
    m = MeshTri1(p, t)
    for _ in range(level):
        m = m.refined()
        b = m.boundary_nodes()
        b = b[on_cylinder(m.p[:, b], geo)]
        p = m.p.copy()
        p[:, b] = snap_to_circle(p[:, b], geo)
        m = MeshTri1(p, m.t)
    m2 = MeshTri2.from_mesh(m)
    tol = 1e-9 * max(geo.L, geo.H)
    m2 = m2.with_boundaries(
        {
            "left": lambda x: np.abs(x[0] - geo.x0) < tol,
            "right": lambda x: np.abs(x[0] - geo.x0 - geo.L) < tol,
            "bottom": lambda x: np.abs(x[1]) < tol,
            "top": lambda x: np.abs(x[1] - geo.H) < tol,
            "cylinder": lambda x: on_cylinder(x, geo),
        }
    )
    dofs = m2.dofs.get_facet_dofs(m2.boundaries["cylinder"]).flatten()
    doflocs = m2.doflocs.copy()
    doflocs[:, dofs] = snap_to_circle(doflocs[:, dofs], geo)
    return replace(m2, doflocs=doflocs)


# --------------------------------------------------------------------------------------------
# discretisation
# --------------------------------------------------------------------------------------------


@dataclass
class Physics:
    rho: float
    eta: float
    g: float = 0.0  # body force per unit mass along x (periodic cell)
    U: float = 0.0  # mean inflow velocity (channel)
    inertia: bool = False  # steady Navier-Stokes instead of Stokes


@dataclass
class Solution:
    geo: Geometry
    phys: Physics
    level: int
    mesh: object
    ub: object
    pb: object
    x: np.ndarray  # full (unreduced) [u; p]
    nu: int
    n_red: int
    iterations: int
    seconds: float
    results: dict = field(default_factory=dict)

    @property
    def u(self):
        return self.x[: self.nu]

    @property
    def p(self):
        return self.x[self.nu :]


def _forms():
    from skfem import BilinearForm, LinearForm
    from skfem.helpers import ddot, div, grad, sym_grad

    @BilinearForm
    def viscous(u, v, w):
        return 2.0 * w.eta * ddot(sym_grad(u), sym_grad(v))

    @BilinearForm
    def divergence(u, q, w):
        return -div(u) * q

    @LinearForm
    def body(v, w):
        return w.rho * w.g * v[0]

    @LinearForm
    def convection(v, w):
        u0, gu0 = w.u0, grad(w.u0)
        c = np.einsum("ij...,j...->i...", gu0, u0)
        return w.rho * np.einsum("i...,i...->...", c, v)

    return viscous, divergence, body, convection


def periodic_map(geo: Geometry, ub, pb):
    """master[i]: the full dof that dof i is identified with (itself unless it lies on the
    right side of a periodic cell, then its left partner at the same height)."""
    nu = ub.N
    master = np.arange(nu + pb.N)
    if geo.kind != "periodic":
        return master
    tol = 1e-8 * geo.H
    groups = [(ub, idx, 0) for idx in ub.split_indices()] + [(pb, np.arange(pb.N), nu)]
    for basis, idx, off in groups:
        loc = basis.doflocs[:, idx]
        left = idx[np.abs(loc[0] - geo.x0) < tol]
        right = idx[np.abs(loc[0] - geo.x0 - geo.L) < tol]
        yl, yr = basis.doflocs[1, left], basis.doflocs[1, right]
        ol, orr = np.argsort(yl), np.argsort(yr)
        assert len(left) == len(right), (len(left), len(right))
        assert np.max(np.abs(yl[ol] - yr[orr]), initial=0.0) < tol, "periodic dofs do not match"
        master[right[orr] + off] = left[ol] + off
    return master


def solve(geo: Geometry, phys: Physics, level: int, verbose=False, **mesh_kw):
    """Solve one refinement level. Returns [Stokes solution] or, with phys.inertia,
    [Stokes solution, steady Navier-Stokes solution]; each carries its results dict.

    Navier-Stokes is solved by defect correction with the Stokes operator, factorised once:
    x_{k+1} = x_k - S^{-1} R(x_k), R the full steady residual. At Re = O(1e-2) each step
    gains about three orders of magnitude, so a few back-substitutions replace the Newton
    solves."""
    from skfem import Basis, ElementTriP1, ElementTriP2, ElementVector, asm

    t0 = time.perf_counter()
    m2 = build_mesh(geo, level, **mesh_kw)
    ub = Basis(m2, ElementVector(ElementTriP2()), intorder=6)
    pb = ub.with_element(ElementTriP1())
    nu, n = ub.N, ub.N + pb.N
    viscous, divergence, body, convection = _forms()
    K = asm(viscous, ub, eta=phys.eta)
    B = asm(divergence, ub, pb)
    f = np.concatenate([asm(body, ub, rho=phys.rho, g=phys.g), np.zeros(pb.N)])
    A = sp.bmat([[K, B.T], [B, None]], format="csr")

    master = periodic_map(geo, ub, pb)
    keep, red = np.unique(master, return_inverse=True)
    P = sp.csr_matrix((np.ones(n), (np.arange(n), red)), shape=(n, len(keep)))

    # Dirichlet data (full numbering): no slip on walls and cylinder; Poiseuille in and out.
    fixed = ub.get_dofs(["bottom", "top", "cylinder"]).all()
    xD = np.zeros(n)
    if geo.kind == "channel":
        ends = ub.get_dofs(["left", "right"]).all()
        on_ends = np.intersect1d(ends, ub.split_indices()[0])
        y = ub.doflocs[1, on_ends]
        xD[on_ends] = 6.0 * phys.U * y * (geo.H - y) / geo.H**2
        fixed = np.union1d(fixed, ends)
    fixed = np.append(fixed, nu)  # pin one pressure dof (pressure defined up to a constant)
    D = np.unique(red[fixed])
    x_red = np.zeros(len(keep))
    x_red[red[fixed]] = xD[fixed]
    free = np.setdiff1d(np.arange(len(keep)), D)

    Ar = (P.T @ A @ P).tocsr()
    lu = spla.splu(Ar[free][:, free].tocsc())
    b = P.T @ f - Ar @ x_red
    x_red[free] = lu.solve(b[free])
    x = P @ x_red
    t_stokes = time.perf_counter() - t0
    out = [Solution(geo, phys, level, m2, ub, pb, x, nu, len(free), 0, t_stokes)]
    out[0].results = postprocess(out[0], A, f, inertia=False)
    if phys.inertia:
        history = []
        for it in range(1, 40):
            conv = asm(convection, ub, u0=ub.interpolate(x[:nu]), rho=phys.rho)
            res = P.T @ (A @ x + np.concatenate([conv, np.zeros(pb.N)]) - f)
            dx = np.zeros(len(keep))
            dx[free] = -lu.solve(res[free])
            x = x + P @ dx
            history.append(np.linalg.norm((P @ dx)[:nu]) / np.linalg.norm(x[:nu]))
            if verbose:
                print(f"    defect correction {it}: |du|/|u| = {history[-1]:.2e}")
            if history[-1] < 1e-13:
                break
        ns = Solution(geo, phys, level, m2, ub, pb, x, nu, len(free), it, time.perf_counter() - t0)
        ns.results = postprocess(ns, A, f, inertia=True)
        ns.results["contraction"] = history[1] / history[0] if len(history) > 1 else float("nan")
        out.append(ns)
    for s in out:
        s.results["seconds"] = s.seconds
    return out


# --------------------------------------------------------------------------------------------
# post-processing
# --------------------------------------------------------------------------------------------


def _surface_force(sol: Solution, boundary: str):
    """Force of the fluid on a boundary per unit depth by integrating the stress,
    -int sigma . n ds with n the outward normal of the fluid domain."""
    from skfem import FacetBasis, Functional
    from skfem.helpers import grad

    fb = FacetBasis(sol.mesh, sol.ub.elem, facets=sol.mesh.boundaries[boundary], intorder=6)
    fpb = fb.with_element(sol.pb.elem)
    eta = sol.phys.eta

    def comp(i):
        @Functional
        def traction(w):
            gu = grad(w.u)
            s = eta * (gu + np.swapaxes(gu, 0, 1))
            t = np.einsum("ij...,j...->i...", s, w.n) - w.p * w.n
            return -t[i]

        return traction.assemble(fb, u=fb.interpolate(sol.u), p=fpb.interpolate(sol.p))

    return comp(0), comp(1)


def _reaction(sol: Solution, A, f, boundaries, inertia):
    """Reaction of the discrete momentum equation at the velocity dofs of the boundaries:
    the variational (Babuska-Miller) force of the fluid on them, per unit depth."""
    from skfem import asm

    r = f - A @ sol.x
    if inertia:
        convection = _forms()[3]
        r[: sol.nu] -= asm(convection, sol.ub, u0=sol.ub.interpolate(sol.u), rho=sol.phys.rho)
    d = sol.ub.get_dofs(boundaries).all()
    ix, iy = sol.ub.split_indices()
    return float(r[np.intersect1d(d, ix)].sum()), float(r[np.intersect1d(d, iy)].sum())


def centreline_points(geo: Geometry, n=200):
    """n points on y = H/2 from the rear of the cylinder (s = 0) to the front of the next
    cylinder downstream (s = L - 2R), through the periodic side for the periodic cell:
    the abscissa of King & Lind 2021 Fig. 10 (in units of R)."""
    s = np.linspace(0.0, geo.L - 2.0 * geo.R, n)
    x = geo.xc + geo.R + s
    if geo.kind == "periodic":
        x = np.where(x > geo.x0 + geo.L, x - geo.L, x)
    return s, np.vstack([x, np.full_like(x, geo.yc)])


def evaluate(sol: Solution, pts):
    """Velocity (2xN) at points: element search on the straight-sided mesh, then the inverse
    isoparametric map of the curved element. Points on or inside the cylinder get 0."""
    from skfem import MeshTri1

    m1 = MeshTri1(sol.mesh.p, sol.mesh.t)
    r = np.hypot(pts[0] - sol.geo.xc, pts[1] - sol.geo.yc)
    fluid = r > sol.geo.R * (1.0 + 1e-12)
    out = np.zeros((2, pts.shape[1]))
    q = pts[:, fluid]
    cells = m1.element_finder()(*q)
    X = sol.ub.mapping.invF(q[:, :, None], tind=cells)
    vals = np.zeros((2, q.shape[1]))
    for k in range(sol.ub.Nbfun):
        phi = sol.ub.elem.gbasis(sol.ub.mapping, X, k, tind=cells)[0].value[:, :, 0]
        vals += phi * sol.u[sol.ub.element_dofs[k, cells]]
    out[:, fluid] = vals
    return out


def flow_measures(ub, u):
    """Fluid area, mean of u_x over it, and the flux Q through x = x0 (per unit depth)."""
    from skfem import FacetBasis, Functional

    @Functional
    def ux(w):
        return w.u[0]

    @Functional
    def one(w):
        return 1.0 + 0.0 * w.x[0]

    @Functional
    def inflow(w):
        return -(w.u[0] * w.n[0] + w.u[1] * w.n[1])  # through x = x0, n = -e_x

    area = one.assemble(ub)
    u_fluid = ux.assemble(ub, u=ub.interpolate(u)) / area
    fb = FacetBasis(ub.mesh, ub.elem, facets=ub.mesh.boundaries["left"], intorder=6)
    return area, u_fluid, inflow.assemble(fb, u=fb.interpolate(u))


def postprocess(sol: Solution, A, f, inertia):
    geo, phys = sol.geo, sol.phys
    area, u_fluid, Q = flow_measures(sol.ub, sol.u)
    u_bulk = Q / geo.H
    Fx, Fy = _reaction(sol, A, f, ["cylinder"], inertia)
    Wx, _ = _reaction(sol, A, f, ["bottom", "top"], inertia)
    Sx, Sy = _surface_force(sol, "cylinder")
    body = phys.rho * phys.g * area
    # The body force acts on the fluid only; the pressure-driven flow with the same
    # modified pressure (p - rho g x) also pushes on the cylinder: F_pd = F + rho g pi R^2.
    F_pd = Fx + phys.rho * phys.g * math.pi * geo.R**2
    return dict(
        kind=geo.kind,
        L=geo.L,
        H=geo.H,
        R=geo.R,
        level=sol.level,
        inertia=int(inertia),
        h_cyl=H_CYL0 / 2**sol.level,
        elements=int(sol.mesh.t.shape[1]),
        unknowns=int(sol.n_red),
        fluid_area=area,
        drag=Fx,
        lift=Fy,
        drag_surface=Sx,
        lift_surface=Sy,
        wall_force=Wx,
        body_force=body,
        balance_residual=(body - Fx - Wx) / body if phys.g else float("nan"),
        flow_rate=Q,
        u_mean_fluid=u_fluid,
        u_bulk=u_bulk,
        K_fluid=Fx / (phys.eta * u_fluid),
        K_bulk=Fx / (phys.eta * u_bulk),
        drag_pd=F_pd,
        K_pd=F_pd / (phys.eta * u_bulk),
        Re=phys.rho * u_fluid * geo.R / phys.eta,
        iterations=sol.iterations,
    )


# --------------------------------------------------------------------------------------------
# studies
# --------------------------------------------------------------------------------------------


def kl_geometry(L=KL["L"]):
    return Geometry("periodic", L=L, H=KL["H"], R=KL["R"])


def kl_physics(inertia=False):
    return Physics(rho=KL["rho"], eta=KL["eta0"], g=KL["g"], inertia=inertia)


def channel_geometry(half_length=15.0):
    """The confined-cylinder benchmark: blockage R/(H/2) = 0.5, cylinder at x = 0 between
    an inlet at -half_length R and an outlet at +half_length R (R = 1, U = 1, eta = 1)."""
    return Geometry("channel", L=2 * half_length, H=4.0, R=1.0, x0=-half_length, xc=0.0)


CHANNEL_PHYSICS = Physics(rho=1.0, eta=1.0, U=1.0)

# the quantities of cell_results.csv, and the columns of the convergence tables
CELL_QUANTITIES = [
    "drag",
    "lift",
    "drag_surface",
    "wall_force",
    "body_force",
    "flow_rate",
    "u_mean_fluid",
    "u_bulk",
    "K_fluid",
    "K_bulk",
    "K_pd",
    "Re",
]
CONV_COLUMNS = (
    ["level", "h_cyl", "elements", "unknowns"]
    + CELL_QUANTITIES
    + ["balance_residual", "iterations", "seconds"]
)
STUDIED = ["drag", "flow_rate", "u_mean_fluid", "K_fluid", "K_pd"]


def observed_orders(values):
    """Observed orders between successive levels (refinement ratio 2; nan for the first
    two) and the Richardson extrapolation from the last three levels."""
    v = np.asarray(values, dtype=float)
    orders = [float("nan")] * min(2, len(v))
    for k in range(2, len(v)):
        d1, d2 = v[k - 1] - v[k - 2], v[k] - v[k - 1]
        orders.append(math.log2(abs(d1 / d2)) if d1 != 0 and d2 != 0 else float("nan"))
    p = orders[-1] if len(v) > 2 else float("nan")
    extrap = v[-1] + (v[-1] - v[-2]) / (2**p - 1) if np.isfinite(p) else v[-1]
    return orders, float(extrap)


def add_convergence(rows, keys=STUDIED):
    """Observed order, extrapolated value and relative error of each level, per key."""
    extrap = {}
    for key in keys:
        orders, ex = observed_orders([r[key] for r in rows])
        extrap[key] = ex
        for r, o in zip(rows, orders):
            r[f"order_{key}"] = o
            r[f"error_{key}"] = (r[key] - ex) / ex
    return extrap


def write_csv(path, rows, columns):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(columns)
        for r in rows:
            w.writerow([f"{r[c]:.12g}" if isinstance(r[c], float) else r[c] for c in columns])


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return [{k: _num(v) for k, v in r.items()} for r in rows]


def _num(v):
    try:
        return int(v)
    except ValueError:
        try:
            return float(v)
        except ValueError:
            return v


def conv_columns():
    cols = list(CONV_COLUMNS)
    for key in STUDIED:
        cols += [f"order_{key}", f"error_{key}"]
    return cols


def converged_level(rows, tol=1e-3, keys=("drag", "u_mean_fluid", "K_fluid")):
    """First level from which every studied quantity is within tol of its extrapolation."""
    for r in rows:
        if all(abs(r[f"error_{k}"]) < tol for k in keys):
            return r["level"]
    return None


def study_cell(out, levels=LEVELS, verbose=True):
    """King & Lind's cell: Stokes and steady Navier-Stokes on every level."""
    stokes, ns, finest = [], [], None
    for lev in range(levels):
        s, n = solve(kl_geometry(), kl_physics(inertia=True), lev)
        stokes.append(s.results)
        ns.append(n.results)
        finest = (s, n)
        if verbose:
            r, q = s.results, n.results
            print(
                f"  cell level {lev}: {r['unknowns']} unknowns, drag {r['drag']:.10g} N/m, "
                f"<u> {r['u_mean_fluid']:.10g} m/s, K {r['K_fluid']:.10g}; Navier-Stokes "
                f"K {q['K_fluid']:.10g} ({q['iterations']} corrections); {q['seconds']:.1f} s",
                flush=True,
            )
    ex_s = add_convergence(stokes)
    ex_n = add_convergence(ns)
    write_csv(os.path.join(out, "convergence_stokes.csv"), stokes, conv_columns())
    write_csv(os.path.join(out, "convergence_navier_stokes.csv"), ns, conv_columns())

    # the converged numbers: finest level and extrapolation, Stokes and Navier-Stokes
    rows = []
    for name, res, ex in (("stokes", stokes, ex_s), ("navier_stokes", ns, ex_n)):
        f = res[-1]
        for q in CELL_QUANTITIES:
            rows.append(
                dict(
                    model=name,
                    quantity=q,
                    value=f[q],
                    extrapolated=ex.get(q, float("nan")),
                    uncertainty=abs(f[q] - ex[q]) if q in ex else float("nan"),
                    level=f["level"],
                )
            )
    write_csv(
        os.path.join(out, "cell_results.csv"),
        rows,
        ["model", "quantity", "value", "extrapolated", "uncertainty", "level"],
    )

    s, n = finest
    sc, pts = centreline_points(s.geo)
    us, un = evaluate(s, pts), evaluate(n, pts)
    prof = [
        dict(
            s_over_R=float(a),
            x=float(x),
            u=float(b),
            v=float(c),
            u_over_mean=float(b / s.results["u_mean_fluid"]),
            u_navier_stokes=float(d),
            u_over_mean_navier_stokes=float(d / n.results["u_mean_fluid"]),
        )
        for a, x, b, c, d in zip(sc / s.geo.R, pts[0], us[0], us[1], un[0])
    ]
    write_csv(
        os.path.join(out, "centreline.csv"),
        prof,
        ["s_over_R", "x", "u", "v", "u_over_mean", "u_navier_stokes", "u_over_mean_navier_stokes"],
    )
    return stokes, ns, finest


def study_channel(out, levels=CHANNEL_LEVELS, verbose=True):
    """The confined-cylinder benchmark (Newtonian, creeping) on every level, and the
    sensitivity to the channel length."""
    rows = []
    for lev in range(levels):
        (s,) = solve(channel_geometry(), CHANNEL_PHYSICS, lev, h_max=2.0)
        rows.append(s.results)
        if verbose:
            print(
                f"  channel level {lev}: {s.results['unknowns']} unknowns, "
                f"K {s.results['K_bulk']:.10g}, {s.seconds:.1f} s",
                flush=True,
            )
    add_convergence(rows, ["drag", "K_pd"])
    # the wall reaction of the channel includes the inlet and outlet corners: not reported
    drop = ("body_force", "balance_residual", "Re", "wall_force", "iterations")
    cols = [c for c in CONV_COLUMNS if c not in drop]
    write_csv(
        os.path.join(out, "convergence_channel.csv"), rows, cols + ["order_drag", "error_drag"]
    )
    length = []
    for half in (10.0, 15.0, 20.0):
        (s,) = solve(channel_geometry(half), CHANNEL_PHYSICS, 2, h_max=2.0)
        length.append(dict(half_length=half, level=2, K=s.results["drag"], lift=s.results["lift"]))
    write_csv(
        os.path.join(out, "channel_length.csv"), length, ["half_length", "level", "K", "lift"]
    )
    return rows


LONG_CELLS = (6.0, 12.0, 24.0, 48.0, 96.0)
LONG_LEVEL = 2


def study_long_cells(out, verbose=True):
    """K&L's cell (same R, H, rho, eta0, g) lengthened: how K approaches the confined
    benchmark, under each definition of the mean velocity."""
    (ch,) = solve(channel_geometry(), CHANNEL_PHYSICS, LONG_LEVEL, h_max=2.0)
    k_channel = ch.results["K_pd"]  # same level and mesh sizes near the cylinder
    rows = []
    for L in LONG_CELLS:
        (s,) = solve(kl_geometry(L), kl_physics(), LONG_LEVEL, h_max=2.0)
        r = s.results
        rows.append(
            dict(
                L_over_R=L,
                level=LONG_LEVEL,
                drag=r["drag"],
                drag_pd=r["drag_pd"],
                flow_rate=r["flow_rate"],
                u_mean_fluid=r["u_mean_fluid"],
                u_bulk=r["u_bulk"],
                K_fluid=r["K_fluid"],
                K_bulk=r["K_bulk"],
                K_pd=r["K_pd"],
                K_channel=k_channel,
                rel_diff_K_pd=(r["K_pd"] - k_channel) / k_channel,
                rel_diff_K_fluid=(r["K_fluid"] - k_channel) / k_channel,
            )
        )
        if verbose:
            print(
                f"  long cell L = {L:g} R: K_fluid {r['K_fluid']:.8g}, K_bulk "
                f"{r['K_bulk']:.8g}, K_pd {r['K_pd']:.8g}, {s.seconds:.1f} s",
                flush=True,
            )
    write_csv(os.path.join(out, "long_cells.csv"), rows, list(rows[0].keys()))
    return rows


def figure(out, level=LEVELS - 2):
    """Velocity magnitude in K&L's cell with the cylinder drawn; centre-line u/<u>; the
    convergence of drag, <u> and K."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    (s,) = solve(kl_geometry(), kl_physics(), level)
    geo = s.geo
    ubx = s.ub.split_bases()[0]
    ix, iy = s.ub.split_indices()
    mag = np.hypot(s.u[ix], s.u[iy])
    m, z = ubx.refinterp(mag, nrefs=1)
    fig = plt.figure(figsize=(12, 8.2))
    ax = fig.add_axes([0.06, 0.50, 0.62, 0.46])
    tpc = ax.tripcolor(m.p[0], m.p[1], m.t.T, z, shading="gouraud", cmap="viridis")
    ax.add_patch(Circle((geo.xc, geo.yc), geo.R, facecolor="0.85", edgecolor="k", lw=1.2))
    ax.plot([geo.x0, geo.x0 + geo.L], [geo.yc, geo.yc], "w--", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlim(geo.x0, geo.x0 + geo.L)
    ax.set_ylim(0, geo.H)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    r = s.results
    ax.set_title(
        f"|u| [m/s], Stokes, level {level}: <u> = {r['u_mean_fluid']:.5f} m/s, "
        f"F = {r['drag']:.2f} N/m, K = {r['K_fluid']:.3f}",
        fontsize=10,
    )
    fig.colorbar(tpc, ax=ax, fraction=0.03, pad=0.02)

    prof = read_csv(os.path.join(out, "centreline.csv"))
    ax2 = fig.add_axes([0.76, 0.55, 0.22, 0.38])
    ax2.plot([p["s_over_R"] for p in prof], [p["u_over_mean"] for p in prof], "k-", label="Stokes")
    ax2.plot(
        [p["s_over_R"] for p in prof],
        [p["u_over_mean_navier_stokes"] for p in prof],
        "r:",
        label=f"Navier-Stokes, Re = {r['Re']:.3f}",
    )
    ax2.set_xlabel("s / R (0: rear of a cylinder, 4: next front)")
    ax2.set_ylabel("u / <u> on y = H/2")
    ax2.set_xlim(0, geo.L - 2 * geo.R)
    ax2.set_ylim(bottom=0)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8, loc="lower center")

    conv = read_csv(os.path.join(out, "convergence_stokes.csv"))
    ch = read_csv(os.path.join(out, "convergence_channel.csv"))
    ax3 = fig.add_axes([0.08, 0.07, 0.38, 0.33])
    h = np.array([c["h_cyl"] for c in conv])
    for key, lab, mk in (
        ("drag", "drag F (cell)", "o"),
        ("u_mean_fluid", "<u> (cell)", "s"),
        ("K_fluid", "K = F/(eta0 <u>) (cell)", "^"),
    ):
        ax3.loglog(h[:-1], [abs(c[f"error_{key}"]) for c in conv][:-1], mk + "-", label=lab)
    hc = np.array([c["h_cyl"] for c in ch])
    ax3.loglog(
        hc[:-1], [abs(c["error_drag"]) for c in ch][:-1], "v--", label="K (confined benchmark)"
    )
    ax3.loglog(h, 0.5 * abs(conv[0]["error_drag"]) * (h / h[0]) ** 4, "k:", label="slope 4")
    ax3.set_title("levels 0..3 against the Richardson extrapolation", fontsize=9)
    ax3.axhline(1e-3, color="0.5", lw=0.8)
    ax3.text(h[-1], 1.2e-3, "0.1 %", fontsize=8, color="0.4")
    ax3.set_xlabel("element size on the cylinder h / R")
    ax3.set_xticks(h)
    ax3.set_xticklabels([f"1/{round(1 / v)}" for v in h])
    ax3.minorticks_off()
    ax3.set_ylabel("|relative error| vs extrapolation")
    ax3.grid(alpha=0.3, which="both")
    ax3.legend(fontsize=8)

    lc = read_csv(os.path.join(out, "long_cells.csv"))
    ax4 = fig.add_axes([0.57, 0.07, 0.40, 0.33])
    Ls = [c["L_over_R"] for c in lc]
    ax4.semilogx(Ls, [c["K_fluid"] for c in lc], "o-", label="F / (eta0 <u>_fluid)")
    ax4.semilogx(Ls, [c["K_bulk"] for c in lc], "s-", label="F / (eta0 Q/H)")
    ax4.semilogx(Ls, [c["K_pd"] for c in lc], "^-", label="(F + rho g pi R^2) / (eta0 Q/H)")
    ax4.axhline(
        ch[-1]["K_pd"],
        color="k",
        lw=0.8,
        ls="--",
        label=f"confined channel, this solver: {ch[-1]['K_pd']:.3f}",
    )
    ax4.set_xlabel("cell length L / R (K&L: 6)")
    ax4.set_ylabel("K")
    ax4.set_xticks(Ls)
    ax4.set_xticklabels([f"{v:g}" for v in Ls])
    ax4.grid(alpha=0.3)
    ax4.legend(fontsize=8, loc="lower right")
    path = os.path.join(out, "cylinder_array.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("task", choices=["level", "cell", "channel", "longcells", "figure", "all"])
    ap.add_argument("level", nargs="?", type=int, default=0, help="the level for `level`")
    ap.add_argument("--out", default=HERE, help="directory of the CSV and PNG files")
    ap.add_argument("--inertia", action="store_true", help="`level`: also Navier-Stokes")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    if a.task == "level":
        for s in solve(kl_geometry(), kl_physics(a.inertia), a.level, verbose=True):
            print(f"-- {'Navier-Stokes' if s.results['inertia'] else 'Stokes'}, level {a.level}")
            for k, v in s.results.items():
                print(f"{k:18s} {v}")
        return 0
    if a.task in ("cell", "all"):
        study_cell(a.out)
    if a.task in ("channel", "all"):
        study_channel(a.out)
    if a.task in ("longcells", "all"):
        study_long_cells(a.out)
    if a.task in ("figure", "all"):
        print("  figure:", figure(a.out))
    print(f"done in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
