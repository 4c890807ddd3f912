//! What a run reports: the outputs every scene shares ([`SharedOutputs`]), how each is computed,
//! and how a scene declares its own ([`outputs!`](crate::outputs), e.g. the channel's
//! `centreline_velocity`, the jet's `jet_deflection`: see their scene files). The scene registry
//! ([`crate::scene`]) assembles the shared outputs and every scene's into the FMU's outputs
//! (`scene::Outputs`); an output that does not apply to the running scene holds 0.
//!
//! Particle extents include half a lattice spacing on each side (each particle stands for a
//! dx x dx square), so the initial drop measures its diameter D, not D - dx.
//!
//! | output | definition |
//! |---|---|
//! | `drop_width` | (max s - min s) over fluid particles + dx; s is the along-plate coordinate. Elliptical drop: extent along x. |
//! | `drop_height` | max distance d of fluid from the plate + dx/2. Elliptical drop: extent along y. |
//! | `spread_front` | max s + dx/2: how far the fluid reaches downhill of the impact point |
//! | `spread_back` | -(min s - dx/2): how far the fluid reaches uphill of the impact point |
//! | `wall_force_normal` | force of the fluid on the plate per unit depth along -n (into the plate), from the last step's corrector stage |
//! | `wall_force_tangential` | same force along the downhill tangent t |
//! | `kinetic_energy` | sum of m v^2 / 2 over fluid particles [J/m] |
//! | `volume_error` | sum(m / rho) / (N m / rho0) - 1: the fluid's volume change through compression. Under isph, where sum(m / rho) is constant by construction, the area the particles cover ([`covered_area`]) over N dx^2, minus 1 (drop scenes; the closed channel keeps sum(m / rho)); in 3D the covered volume ([`covered_volume`]) over N dx^3, minus 1 |
//! | `max_conformation_trace` | max tr(A) over fluid particles; 0 for models without a conformation tensor |
//! | `min_conformation_det` | min det(A) over fluid particles (> 0 while A is positive definite); 1 without a tensor |
//! | `time_step` | the last full time step taken |
//! | `particle_count` | number of fluid particles |
//! | `void_fraction` | area of holes enclosed by fluid over the fluid's area, on cells of 2 dx (see [`crate::health`]) |
//! | `plate_displacement` | distance the plate has moved along -n (the integral of the `plate_velocity` input); 0 without a plate |
//! | `drop_width_transverse` | 3D: (max b - min b) + dx, b the coordinate along the plate's horizontal n x t (across the downhill direction); 0 in 2D |
//! | `wall_force_normal_total`, `wall_force_tangential_total` | the wall force in newtons: in 3D the force on the wall itself, in 2D the per-depth force times the parameter `depth` |
//! | `kinetic_energy_total` | the kinetic energy in joules: in 3D the fluid's, in 2D per depth times `depth` |
//!
//! Every unit holds in both dimensions: the per-depth outputs (`wall_force_normal`,
//! `wall_force_tangential`, `kinetic_energy` [J/m]) hold 0 in 3D, where their `_total`
//! counterparts carry the values, and `drop_width_transverse` holds 0 in 2D.
//!
//! Outputs that do not apply to a scene hold 0 (`min_conformation_det` 1), never NaN: the drop
//! fills these; the channel only the health figures (and its own three); the elliptical drop
//! fills width and height as its extents along x and y; the jet measures width, height and spread
//! on the heap only (see [`crate::scene::jet`]), and its wall forces are those on all its walls.
//!
//! At a communication time between two internal steps, every output is interpolated linearly
//! between the two internal states (see `Simulation::advance_to`), so outputs at a given time do
//! not depend on the communication step size.
//!
//! The wall force is the force the wall particles exert on the fluid in the corrector stage, with
//! the sign flipped. Because the same force moves the fluid in that stage, its time integral
//! equals the change of the drop's momentum minus the gravity impulse, to round-off.

use crate::boundary::plate::Plate;
use crate::dim::Vector;
use crate::eos::Eos;
use crate::kernel::Kernel;
use crate::neighbors::{Domain, Grid, NeighborList};
use crate::particles::Fluid;
use crate::state::State;
use crate::Vec2;
use rayon::prelude::*;

/// One row of the output table: an FMU output (a scalar; an array row of [`outputs!`](crate::outputs!) gives
/// one per element).
#[derive(Debug, Clone, Copy)]
pub struct OutputSpec {
    pub name: &'static str,
    pub value_reference: u32,
    pub unit: &'static str,
    pub description: &'static str,
}

/// An array row of the output table: a distribution (the load along the plate in bins) that
/// is `len` scalar outputs `name_001..` with the value references `first_element_vr..` in
/// FMI 2.0 and FMI 3.0 alike, and in FMI 3.0 also one Float64 array variable of its own
/// (`value_reference`, `<Dimension start="len"/>`) whose values are those elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputArray {
    pub name: &'static str,
    /// The FMI 3.0 array variable's value reference.
    pub value_reference: u32,
    /// Value reference of element 1 (`name_001`); element k has `first_element_vr + k - 1`.
    pub first_element_vr: u32,
    pub len: usize,
    pub unit: &'static str,
    /// The array variable's description.
    pub description: &'static str,
    /// Each element's description, `{k}` standing for its 1-based index.
    pub element_description: &'static str,
}

impl OutputArray {
    /// The scalar rows of the elements, in order: `name_001`, `name_002`, ...
    pub fn element_rows(&self) -> Vec<OutputSpec> {
        (1..=self.len)
            .map(|k| OutputSpec {
                name: leak(format!("{}_{k:03}", self.name)),
                value_reference: self.first_element_vr + k as u32 - 1,
                unit: self.unit,
                description: leak(self.element_description.replace("{k}", &k.to_string())),
            })
            .collect()
    }
}

/// The element names and descriptions live as long as the tables, which are built once per
/// process (`OnceLock`): leaking them is how they become `&'static` like the scalar rows'.
fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// The scalar rows of a group from one row per field: an array row's field becomes its
/// elements ([`OutputArray::element_rows`]).
pub fn expand_arrays(fields: &[OutputSpec], arrays: &[OutputArray]) -> Vec<OutputSpec> {
    let mut rows = Vec::new();
    for f in fields {
        match arrays.iter().find(|a| a.name == f.name) {
            Some(a) => rows.extend(a.element_rows()),
            None => rows.push(*f),
        }
    }
    rows
}

/// A field of an output group: a scalar (`f64`) or an array row's values (`[f64; N]`).
pub trait OutputField {
    fn push_to(&self, out: &mut Vec<f64>);
    fn take_from(&mut self, values: &mut std::slice::Iter<'_, f64>);
}

impl OutputField for f64 {
    fn push_to(&self, out: &mut Vec<f64>) {
        out.push(*self);
    }
    fn take_from(&mut self, values: &mut std::slice::Iter<'_, f64>) {
        *self = *values.next().expect("one value per row");
    }
}

impl<const N: usize> OutputField for [f64; N] {
    fn push_to(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(self);
    }
    fn take_from(&mut self, values: &mut std::slice::Iter<'_, f64>) {
        for x in self {
            *x = *values.next().expect("one value per row");
        }
    }
}

/// A group of outputs: a struct of `f64` fields (and `[f64; N]` fields for array rows) that
/// are rows of the output table, declared once with [`outputs!`](crate::outputs).
pub trait OutputGroup {
    /// The scalar rows, in field order (an array row as its elements).
    fn rows() -> &'static [OutputSpec];
    /// The array rows, in field order.
    const ARRAYS: &'static [OutputArray];
    /// Append the values in the order of [`OutputGroup::rows`].
    fn push_values(&self, out: &mut Vec<f64>);
    /// Set the values from `v`, in the order of [`OutputGroup::rows`]; returns the rest of `v`.
    fn take_values<'a>(&mut self, v: &'a [f64]) -> &'a [f64];
}

/// The type of an output field: `f64`, or `[f64; len]` for an array row.
#[doc(hidden)]
#[macro_export]
macro_rules! __output_field_type {
    () => {
        f64
    };
    ($len:expr) => {
        [f64; $len]
    };
}

/// Declare a group of outputs: each field is written once with its row (FMU name = field name,
/// value reference, unit, description = the field's documentation); the macro generates the
/// struct and its [`OutputGroup`] implementation. A row followed by `; array [len] vr V;
/// "description"` is an array row ([`OutputArray`]): its field is `[f64; len]`, its elements
/// are the scalar outputs `name_001..` from the row's value reference on (the row's
/// description with `{k}` for the index), and V is the FMI 3.0 array variable's.
///
/// ```ignore
/// viscosph::outputs! {
///     /// The jet's own outputs.
///     pub struct JetOutputs {
///         jet_deflection: vr 119, unit "m"; "Jet: horizontal offset of the falling column",
///     }
/// }
/// ```
#[macro_export]
macro_rules! outputs {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $( $field:ident : vr $vr:literal, unit $unit:literal; $desc:literal
               $(; array [$len:expr] vr $avr:literal; $adesc:literal)? ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
        $vis struct $name {
            $( #[doc = $desc] pub $field: $crate::__output_field_type!($($len)?), )*
        }

        impl $crate::diagnostics::OutputGroup for $name {
            fn rows() -> &'static [$crate::diagnostics::OutputSpec] {
                static ROWS: std::sync::OnceLock<Vec<$crate::diagnostics::OutputSpec>> =
                    std::sync::OnceLock::new();
                const FIELDS: &[$crate::diagnostics::OutputSpec] = &[
                    $(
                        $crate::diagnostics::OutputSpec {
                            name: stringify!($field),
                            value_reference: $vr,
                            unit: $unit,
                            description: $desc,
                        },
                    )*
                ];
                ROWS.get_or_init(|| $crate::diagnostics::expand_arrays(FIELDS, Self::ARRAYS))
            }
            const ARRAYS: &'static [$crate::diagnostics::OutputArray] = &[
                $($(
                    $crate::diagnostics::OutputArray {
                        name: stringify!($field),
                        value_reference: $avr,
                        first_element_vr: $vr,
                        len: $len,
                        unit: $unit,
                        description: $adesc,
                        element_description: $desc,
                    },
                )?)*
            ];
            fn push_values(&self, out: &mut Vec<f64>) {
                $( $crate::diagnostics::OutputField::push_to(&self.$field, out); )*
                let _ = out;
            }
            fn take_values<'a>(&mut self, v: &'a [f64]) -> &'a [f64] {
                let (own, rest) = v.split_at(Self::rows().len());
                let own = &mut own.iter();
                $( $crate::diagnostics::OutputField::take_from(&mut self.$field, own); )*
                let _ = own;
                rest
            }
        }
    };
}

outputs! {
    /// The outputs every scene has (see the module documentation for their definitions).
    pub struct SharedOutputs {
        drop_width: vr 101, unit "m"; "Extent of the fluid along the plate (downhill)",
        drop_height: vr 102, unit "m"; "Largest distance of fluid from the plate",
        wall_force_normal: vr 103, unit "N/m"; "2D: force of the fluid on the plate per unit depth, normal component, positive into the plate; 0 in 3D (see wall_force_normal_total)",
        wall_force_tangential: vr 104, unit "N/m"; "2D: force of the fluid on the plate per unit depth, tangential component, positive downhill; 0 in 3D (see wall_force_tangential_total)",
        spread_front: vr 105, unit "m"; "Furthest reach of the fluid downhill of the impact point, along the plate",
        spread_back: vr 106, unit "m"; "Furthest reach of the fluid uphill of the impact point, along the plate",
        kinetic_energy: vr 107, unit "J/m"; "2D: kinetic energy of the fluid per unit depth; 0 in 3D (see kinetic_energy_total)",
        volume_error: vr 108, unit "1"; "Relative change of the fluid volume sum(m/rho)",
        max_conformation_trace: vr 109, unit "1"; "Largest trace of the conformation tensor (0 without one)",
        min_conformation_det: vr 110, unit "1"; "Smallest determinant of the conformation tensor (1 without one)",
        time_step: vr 111, unit "s"; "Last time step of the solver",
        particle_count: vr 112, unit ""; "Number of fluid particles",
        void_fraction: vr 113, unit "1"; "2D: area of holes torn into the fluid over the fluid's area (tensile-instability fracture measure); 0 in 3D (not measured there)",
        plate_displacement: vr 117, unit "m"; "Distance the plate has moved along its normal, away from the fluid, driven by the plate_velocity input",
        drop_width_transverse: vr 190, unit "m"; "3D: extent of the fluid across the plate (along the horizontal n x t, perpendicular to the downhill direction); 0 in 2D (no direction across the plane of the flow)",
        wall_force_normal_total: vr 191, unit "N"; "Force of the fluid on the plate, normal component, positive into the plate: in 3D the force on the wall, in 2D wall_force_normal times the parameter depth",
        wall_force_tangential_total: vr 192, unit "N"; "Force of the fluid on the plate, tangential component, positive downhill: in 3D the force on the wall, in 2D wall_force_tangential times the parameter depth",
        kinetic_energy_total: vr 193, unit "J"; "Kinetic energy of the fluid: in 3D the fluid's, in 2D kinetic_energy times the parameter depth",
    }
}

outputs! {
    /// The group of a scene without outputs of its own.
    pub struct NoOutputs {}
}

impl SharedOutputs {
    /// Compute every shared output from a state. `dx` is the lattice spacing, `rho0` the
    /// reference density. In 2D the `_total` outputs are left 0 (they need the depth:
    /// [`SharedOutputs::complete_2d`]); in 3D the per-depth ones are 0 and the totals hold the
    /// force and energy themselves.
    pub fn compute<const N: usize>(st: &State<N>, dx: f64, rho0: f64) -> Self
    where
        nalgebra::Const<N>: nalgebra::DimMin<nalgebra::Const<N>, Output = nalgebra::Const<N>>,
    {
        let fl = &st.fluid;
        let n = fl.len();
        let mut o = SharedOutputs {
            particle_count: n as f64,
            time_step: st.last_dt,
            void_fraction: st.void_fraction,
            min_conformation_det: 1.0,
            ..Default::default()
        };
        if n == 0 {
            return o;
        }
        let (mut s_lo, mut s_hi, mut d_lo, mut d_hi) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let (mut b_lo, mut b_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        // In 3D the direction across the plate: its horizontal n x t (y without a plate).
        let across = (N == 3).then(|| match st.plate() {
            Some(p) => {
                let (n3, t3) = (
                    nalgebra::Vector3::from_iterator(p.n.iter().copied()),
                    nalgebra::Vector3::from_iterator(p.t.iter().copied()),
                );
                let b = n3.cross(&t3);
                (p.origin, Vector::<N>::from_iterator(b.iter().copied()))
            }
            None => {
                let mut b = Vector::<N>::zeros();
                b[1] = 1.0;
                (Vector::<N>::zeros(), b)
            }
        });
        let mut volume = 0.0;
        let mut ke = 0.0;
        for i in 0..n {
            let (s, d) = match st.plate() {
                Some(p) => (p.s(&fl.x[i]), p.d(&fl.x[i])),
                None => (fl.x[i][0], fl.x[i][N - 1]),
            };
            s_lo = s_lo.min(s);
            s_hi = s_hi.max(s);
            d_lo = d_lo.min(d);
            d_hi = d_hi.max(d);
            if let Some((origin, b)) = &across {
                let c = (fl.x[i] - origin).dot(b);
                b_lo = b_lo.min(c);
                b_hi = b_hi.max(c);
            }
            volume += fl.mass / fl.rho[i];
            ke += 0.5 * fl.mass * fl.v[i].norm_squared();
        }
        o.drop_width = s_hi - s_lo + dx;
        o.drop_height = match st.plate() {
            Some(_) => d_hi + 0.5 * dx,
            None => d_hi - d_lo + dx,
        };
        o.spread_front = s_hi + 0.5 * dx;
        o.spread_back = -(s_lo - 0.5 * dx);
        o.volume_error = volume / (n as f64 * fl.mass / rho0) - 1.0;
        let (mut normal, mut tangential) = (0.0, 0.0);
        if let Some(p) = st.plate() {
            o.plate_displacement = p.displacement;
            normal = -st.wall_force.dot(&p.n);
            tangential = st.wall_force.dot(&p.t);
        }
        if across.is_some() {
            o.drop_width_transverse = b_hi - b_lo + dx;
            o.wall_force_normal_total = normal;
            o.wall_force_tangential_total = tangential;
            o.kinetic_energy_total = ke;
        } else {
            o.wall_force_normal = normal;
            o.wall_force_tangential = tangential;
            o.kinetic_energy = ke;
        }
        if !fl.conf.is_empty() {
            o.max_conformation_trace = fl.conf.iter().map(|a| a.trace()).fold(f64::MIN, f64::max);
            o.min_conformation_det = fl
                .conf
                .iter()
                .map(|a| a.determinant())
                .fold(f64::MAX, f64::min);
        }
        o
    }

    /// The 2D outputs in newtons and joules: the per-depth force and energy times `depth` \[m\]
    /// (the length across the plane of the flow the run stands for).
    pub fn complete_2d(&mut self, depth: f64) {
        self.wall_force_normal_total = self.wall_force_normal * depth;
        self.wall_force_tangential_total = self.wall_force_tangential * depth;
        self.kinetic_energy_total = self.kinetic_energy * depth;
    }

    /// [`SharedOutputs::compute`], with the volume error measured geometrically
    /// ([`covered_area`]) when the scheme is `incompressible`: every particle keeps the volume
    /// m / rho0 there, so sum(m / rho) could not fail.
    pub fn compute_for(st: &State, dx: f64, rho0: f64, incompressible: bool) -> Self {
        let mut o = Self::compute(st, dx, rho0);
        if incompressible && !st.fluid.is_empty() {
            let area = covered_area(&st.fluid.x, dx, st.plate());
            o.volume_error = area / (st.fluid.len() as f64 * dx * dx) - 1.0;
        }
        o
    }
}

/// Raster cells per particle spacing of [`covered_area`].
pub const AREA_CELLS_PER_DX: f64 = 8.0;

/// The area the particles cover, measured on a raster of dx / 8 cells in the plate's frame (or
/// the global one): the morphological closing of the particle positions, i.e. the set of points
/// within dx of a particle (which bridges the gaps between neighbours up to 2 dx apart), eroded
/// by dx / 2 (which brings a free surface back from dx beyond its outermost particles to dx / 2
/// beyond them, where a particle's dx x dx cell ends, and the plate side back to the plate line).
/// On the initial lattice drop this exceeds N dx^2 by 0.32 % at 20 particles per diameter and
/// by 0.21 % at 40 (the closing rounds the lattice's staircase; test
/// `covered_area_of_a_lattice_drop_is_its_particle_area`); it shrinks when particles crowd
/// together and grows when they spread apart, which sum(m / rho) of an incompressible scheme
/// cannot see.
pub fn covered_area(x: &[Vec2], dx: f64, plate: Option<&Plate>) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let pts: Vec<(f64, f64)> = match plate {
        Some(p) => x.iter().map(|x| (p.s(x), p.d(x))).collect(),
        None => x.iter().map(|x| (x.x, x.y)).collect(),
    };
    let cell = dx / AREA_CELLS_PER_DX;
    let (r_dil, r_ero) = (dx, 0.5 * dx);
    let pad = r_dil + 3.0 * cell;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(a, b) in &pts {
        x0 = x0.min(a);
        x1 = x1.max(a);
        y0 = y0.min(b);
        y1 = y1.max(b);
    }
    let (x0, y0) = (x0 - pad, y0 - pad);
    let nx = ((x1 + pad - x0) / cell).ceil() as usize + 1;
    let ny = ((y1 + pad - y0) / cell).ceil() as usize + 1;
    if nx.saturating_mul(ny) > 200_000_000 {
        return f64::NAN;
    }
    let centre = |k: usize, x0: f64| x0 + (k as f64 + 0.5) * cell;
    // Dilation: every cell whose centre is within r_dil of a particle.
    let mut covered = vec![false; nx * ny];
    let rc = (r_dil / cell).ceil() as i64 + 1;
    for &(a, b) in &pts {
        let (ci, cj) = (((a - x0) / cell) as i64, ((b - y0) / cell) as i64);
        for j in (cj - rc).max(0)..=(cj + rc).min(ny as i64 - 1) {
            for i in (ci - rc).max(0)..=(ci + rc).min(nx as i64 - 1) {
                let (u, v) = (centre(i as usize, x0) - a, centre(j as usize, y0) - b);
                if u * u + v * v <= r_dil * r_dil {
                    covered[j as usize * nx + i as usize] = true;
                }
            }
        }
    }
    // Erosion: a covered cell within r_ero of an uncovered cell is removed. Only uncovered cells
    // next to covered ones can reach a covered cell first.
    let mut eroded = covered.clone();
    let re = (r_ero / cell).ceil() as i64;
    for j in 0..ny {
        for i in 0..nx {
            if covered[j * nx + i] {
                continue;
            }
            let edge = (i > 0 && covered[j * nx + i - 1])
                || (i + 1 < nx && covered[j * nx + i + 1])
                || (j > 0 && covered[(j - 1) * nx + i])
                || (j + 1 < ny && covered[(j + 1) * nx + i]);
            if !edge {
                continue;
            }
            for q in (j as i64 - re).max(0)..=(j as i64 + re).min(ny as i64 - 1) {
                for p in (i as i64 - re).max(0)..=(i as i64 + re).min(nx as i64 - 1) {
                    let (u, v) = ((p - i as i64) as f64 * cell, (q - j as i64) as f64 * cell);
                    if u * u + v * v <= r_ero * r_ero {
                        eroded[q as usize * nx + p as usize] = false;
                    }
                }
            }
        }
    }
    eroded.iter().filter(|&&c| c).count() as f64 * cell * cell
}

/// Raster cells per particle spacing of [`covered_volume`].
pub const VOLUME_CELLS_PER_DX: f64 = 4.0;

/// The volume the particles `x` cover in 3D, the counterpart of [`covered_area`]: the
/// morphological closing of the positions on a raster of dx / 4 cells (global axes), the points
/// within dx of a particle eroded by dx / 2. A cubic lattice of spacing dx covers dx^3 per
/// particle inside; the cut-lattice sphere of the drop reads +2.9 %, +2.5 %, +1.4 % over N dx^3
/// at 10, 16, 30 particles per diameter (the closing rounds its staircase), the same sphere with
/// every particle displaced at random by up to 0.1-0.3 dx per component reads -1.3 % to +0.7 %,
/// 0.0 to +0.4 %, +0.1 to +0.2 % (disorder, not compression: the raster's own scatter). NaN
/// above 2 x 10^8 cells.
pub fn covered_volume(x: &[Vector<3>], dx: f64) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let cell = dx / VOLUME_CELLS_PER_DX;
    let (r_dil, r_ero) = (dx, 0.5 * dx);
    let pad = r_dil + 3.0 * cell;
    let mut lo = [f64::MAX; 3];
    let mut hi = [f64::MIN; 3];
    for p in x {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a] - pad);
            hi[a] = hi[a].max(p[a] + pad);
        }
    }
    let n: [usize; 3] = std::array::from_fn(|a| ((hi[a] - lo[a]) / cell).ceil() as usize + 1);
    if n[0].saturating_mul(n[1]).saturating_mul(n[2]) > 200_000_000 {
        return f64::NAN;
    }
    let idx = |i: usize, j: usize, k: usize| (k * n[1] + j) * n[0] + i;
    let centre = |a: usize, i: i64| lo[a] + (i as f64 + 0.5) * cell;
    // Sets every cell whose centre is within r of p to `value`.
    let stamp = |cells: &mut Vec<bool>, p: [f64; 3], r: f64, value: bool| {
        let rc = (r / cell).ceil() as i64 + 1;
        let c: [i64; 3] = std::array::from_fn(|a| ((p[a] - lo[a]) / cell) as i64);
        let range = |a: usize| (c[a] - rc).max(0)..=(c[a] + rc).min(n[a] as i64 - 1);
        for k in range(2) {
            let dz = centre(2, k) - p[2];
            for j in range(1) {
                let dy = centre(1, j) - p[1];
                for i in range(0) {
                    let dxx = centre(0, i) - p[0];
                    if dxx * dxx + dy * dy + dz * dz <= r * r {
                        cells[idx(i as usize, j as usize, k as usize)] = value;
                    }
                }
            }
        }
    };
    let mut covered = vec![false; n[0] * n[1] * n[2]];
    for p in x {
        stamp(&mut covered, [p[0], p[1], p[2]], r_dil, true);
    }
    // Erosion: every uncovered cell next to a covered one clears the cells within r_ero of it.
    let mut eroded = covered.clone();
    for k in 1..n[2] - 1 {
        for j in 1..n[1] - 1 {
            for i in 1..n[0] - 1 {
                if covered[idx(i, j, k)] {
                    continue;
                }
                let next = [
                    idx(i - 1, j, k),
                    idx(i + 1, j, k),
                    idx(i, j - 1, k),
                    idx(i, j + 1, k),
                    idx(i, j, k - 1),
                    idx(i, j, k + 1),
                ];
                if next.iter().any(|&m| covered[m]) {
                    let p = [
                        centre(0, i as i64),
                        centre(1, j as i64),
                        centre(2, k as i64),
                    ];
                    stamp(&mut eroded, p, r_ero, false);
                }
            }
        }
    }
    eroded.iter().filter(|&&c| c).count() as f64 * cell * cell * cell
}

/// Pressure roughness of a fluid state: the RMS over fluid particles of p_i minus its
/// SPH-smoothed value p~_i = sum_j V_j p_j W_ij / sum_j V_j W_ij (fluid neighbours, Shepard
/// normalised so a uniform field is smooth everywhere, the free surface included), divided by
/// `scale` \[Pa\]. It measures the particle-to-particle pressure noise that Ren 2015 Figs. 3 and 9
/// show and that periodic density reinitialisation removes.
pub fn pressure_roughness<K: Kernel<N>, const N: usize>(
    fl: &Fluid<N>,
    eos: &Eos,
    kernel: &K,
    dom: &Domain,
    scale: f64,
) -> f64 {
    let n = fl.len();
    if n == 0 {
        return 0.0;
    }
    let radius = kernel.radius();
    let grid = Grid::<N>::build(&fl.x, radius, dom);
    let list = NeighborList::build(&grid, &fl.x, &fl.x, radius, dom);
    let pres: Vec<f64> = fl.rho.iter().map(|&r| eos.pressure(r)).collect();
    let dev2: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            let (mut num, mut den) = (0.0, 0.0);
            for &j in list.of(i) {
                let j = j as usize;
                let w = fl.mass / fl.rho[j] * kernel.w(dom.delta(&fl.x[i], &fl.x[j]).norm());
                num += w * pres[j];
                den += w;
            }
            let d = pres[i] - num / den;
            d * d
        })
        .collect();
    (dev2.iter().sum::<f64>() / n as f64).sqrt() / scale
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice_disc(ppd: i64, dx: f64) -> Vec<Vec2> {
        let r = 0.5 * ppd as f64 * dx;
        let mut x = Vec::new();
        for j in -ppd..ppd {
            for i in -ppd..ppd {
                let p = Vec2::new((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
                if p.norm() < r {
                    x.push(p + Vec2::new(0.0, r + dx));
                }
            }
        }
        x
    }

    /// The lattice drop covers its particles' area N dx^2 closely, on and off the plate; the
    /// same drop compressed by 1 % along one axis covers 1 % less (the measure can fail).
    #[test]
    fn covered_area_of_a_lattice_drop_is_its_particle_area() {
        for ppd in [20, 40] {
            let dx = 0.02 / ppd as f64;
            let x = lattice_disc(ppd, dx);
            let n = x.len() as f64;
            let plate = Plate::new(0.0, dx);
            let free = covered_area(&x, dx, None) / (n * dx * dx) - 1.0;
            assert!(free.abs() < 4e-3, "ppd {ppd}: {free}");
            // Resting on the plate (lowest row at dx/2): the plate line bounds it.
            let low: Vec<Vec2> = x.iter().map(|p| p - Vec2::new(0.0, 0.5 * dx)).collect();
            let on = covered_area(&low, dx, Some(&plate)) / (n * dx * dx) - 1.0;
            assert!(on.abs() < 4e-3, "ppd {ppd} on the plate: {on}");
            let squeezed: Vec<Vec2> = x.iter().map(|p| Vec2::new(p.x * 0.99, p.y)).collect();
            let e = covered_area(&squeezed, dx, None) / (n * dx * dx) - 1.0;
            assert!(
                (e - free + 0.01).abs() < 3e-3,
                "ppd {ppd}: squeezed {e} vs {free}"
            );
        }
    }

    /// Disorder alone does not move the measure: a lattice disc whose particles are displaced
    /// at random by up to 0.1 or 0.2 dx per component (the same particles, no compression)
    /// covers N dx^2 within 0.5 %, at 20 and 40 particles per diameter. So the drift of several
    /// per cent that an ISPH drop shows (docs/isph.md) is the particles' arrangement occupying
    /// less area, not the raster reading disorder.
    #[test]
    fn covered_area_of_a_disordered_drop_is_its_particle_area() {
        for ppd in [20, 40] {
            let dx = 0.02 / ppd as f64;
            for (jitter, seed) in [(0.1, 7), (0.2, 11), (0.2, 12)] {
                let x = crate::operators::fixtures::disc(0.01, dx, jitter, seed).x;
                let e = covered_area(&x, dx, None) / (x.len() as f64 * dx * dx) - 1.0;
                assert!(e.abs() < 5e-3, "ppd {ppd}, jitter {jitter}: {e}");
            }
        }
    }
}
