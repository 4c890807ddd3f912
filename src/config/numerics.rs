//! The numerics: resolution, time step, the schemes' knobs and the thread pool.

use super::{enumeration, integer, real, Kind};
pub use crate::rheology::{ConformationMethod, CONFORMATION_METHODS};

pub const ARTIFICIAL_STRESS_KINDS: &[(&str, &str)] = &[
    (
        "fang",
        "principal-stress artificial stress, Fang 2006 eqs. 38-44",
    ),
    (
        "ren",
        "artificial stress keyed to d2W, Ren 2015 eqs. 20a-20b",
    ),
];
pub const VISCOUS_OPERATORS: &[(&str, &str)] = &[
    (
        "auto",
        "the scene's choice: nested for the drops (Fang's scheme as published), laplacian for the channel",
    ),
    (
        "nested",
        "viscous stress inside sigma, through the nested first-derivative operator (Fang 2006 eqs. 8, 27)",
    ),
    (
        "laplacian",
        "solvent viscosity through Morris, Fox & Zhu 1997's viscous Laplacian (the form of King & Lind eq. 8)",
    ),
];
pub const ISPH_FRAMES: &[(&str, &str)] = &[
    (
        "lagrangian",
        "particles move with the flow plus a small shifting velocity (King & Lind 2021 section III.E)",
    ),
    (
        "eulerian",
        "particles stay where they are and the flow is convected through them (King & Lind 2021 section III.A); closed domains only",
    ),
];
pub const ISPH_FREE_SURFACES: &[(&str, &str)] = &[
    (
        "auto",
        "ISPH: normal_stress in the jet scene (its column buckles only with it), zero_pressure elsewhere (the drop keeps its volume best)",
    ),
    (
        "zero_pressure",
        "ISPH: p = 0 on the free surface (King's public code), with the solvent's surface traction in the viscous step",
    ),
    (
        "normal_stress",
        "ISPH: the surface pressure is the solvent's normal stress 2 eta n.D.n of King & Lind 2021 eq. (35a), and the projection's pressure gradient is consistent with it",
    ),
];
pub const VISCOUS_STEPS: &[(&str, &str)] = &[
    (
        "implicit",
        "ISPH: solvent viscosity by an implicit (backward Euler) Laplacian solve, so the viscous limit of King & Lind eq. (28) does not set the step",
    ),
    (
        "explicit",
        "ISPH: solvent viscosity explicit in the predictor, King & Lind eq. (24), with the viscous limit of eq. (28)",
    ),
];
pub const EQUATIONS_OF_STATE: &[(&str, &str)] = &[
    ("linear", "p = c^2 (rho - rho0), Fang 2006 eq. 10"),
    (
        "tait",
        "p = rho0 c^2 / 7 ((rho/rho0)^7 - 1), Ren 2015 eq. 8",
    ),
];

crate::choice_enum!(
    /// Which artificial stress is used against the tensile instability.
    ArtificialStressKind, ARTIFICIAL_STRESS_KINDS, Fang = "fang", Ren = "ren");
crate::choice_enum!(
    /// Equation of state.
    EquationOfState, EQUATIONS_OF_STATE, Linear = "linear", Tait = "tait");
crate::choice_enum!(
    /// ISPH particle motion.
    IsphFrame, ISPH_FRAMES, Lagrangian = "lagrangian", Eulerian = "eulerian");
crate::choice_enum!(
    /// ISPH solvent viscosity: implicit or explicit.
    ViscousStep, VISCOUS_STEPS, Implicit = "implicit", Explicit = "explicit");
crate::choice_enum!(
    /// ISPH free-surface pressure condition (module documentation of `scheme::isph`).
    IsphFreeSurface, ISPH_FREE_SURFACES, Auto = "auto", ZeroPressure = "zero_pressure",
    NormalStress = "normal_stress");
pub const WALL_BOUNDARIES: &[(&str, &str)] = &[
    (
        "auto",
        "The scheme's paper's model on straight walls (wcsph: image, pdri: ghost, isph: mirror); on curved walls dummy particles (wcsph, pdri) or mirror particles (isph)",
    ),
    (
        "image",
        "Fang 2006's boundary + image particles (weakly compressible schemes, straight walls only)",
    ),
    (
        "ghost",
        "Ren 2015's wall + ghost particles (weakly compressible schemes, straight walls only)",
    ),
    (
        "dummy",
        "Adami, Hu & Adams 2012's dummy particles with pressure and velocity extrapolation (weakly compressible schemes, any wall)",
    ),
    (
        "mirror",
        "King & Lind 2021's mirror particles across the local tangent (isph, any wall)",
    ),
];

crate::choice_enum!(
    /// The wall model (`boundary` module documentation).
    WallBoundary, WALL_BOUNDARIES, Auto = "auto", Image = "image", Ghost = "ghost",
    Dummy = "dummy", Mirror = "mirror");
crate::choice_enum!(
    /// How the solvent's viscous force is discretised.
    ViscousOperator, VISCOUS_OPERATORS, Auto = "auto", Nested = "nested", Laplacian = "laplacian");

/// Automatic sound speed over the largest expected flow speed: 10 for about 1 % density
/// variation (see `SceneConfig::resolved_sound_speed`).
pub const SOUND_SPEED_FACTOR: f64 = 10.0;

crate::params! {
    /// How the flow is computed: resolution, time step, the schemes' own knobs (each says which
    /// scheme reads it) and the thread pool.
    pub struct Numerics {
        dimension: i64 = integer(2, 2, 3), vr 70, unit "";
            "Space dimensions: 2 (a planar flow, forces per unit depth) or 3 (forces in newtons): the drop as a sphere (or, drop_shape = slab, a slab periodic across) on a plane plate, the elliptical drop as a sphere and the channel between two planes, under every scheme (wcsph and pdri with dummy wall particles, isph with mirror particles); the jet as a round jet through a circular nozzle of diameter jet_width (measured under wcsph and pdri); the other scenes refuse 3 by name",
        particles_per_diameter: i64 = integer(20, 4, 4000), vr 19, unit "";
            "Resolution: lattice spacing dx = drop_diameter / particles_per_diameter",
        sound_speed: f64 = real(0.0, 0.0, 1.0e5), vr 20, unit "m/s";
            "Artificial speed of sound c in the equation of state; 0 = automatic: 10 times the largest speed the scene can reach (the drop: impact speed plus free fall plus max_plate_speed; the jet: its inflow up to max_jet_velocity; the channel and the cylinder array: their flow; the elliptical drop: its own 1400 m/s), for about 1 % density variation. Ignored under isph (incompressible: no equation of state)",
        artificial_viscosity_alpha: f64 = real(1.0, 0.0, 10.0), vr 21, unit "1";
            "Monaghan artificial viscosity alpha (Fang 2006 eq. 31). Ignored under isph",
        artificial_viscosity_beta: f64 = real(2.0, 0.0, 10.0), vr 22, unit "1";
            "Monaghan artificial viscosity beta (Fang 2006 eq. 31). Ignored under isph",
        artificial_stress_epsilon: f64 = real(0.5, 0.0, 1.0), vr 23, unit "1";
            "Artificial stress epsilon against the tensile instability (Fang 2006 eq. 42); 0 switches it off. Ignored under isph (no tensile instability to counter)",
        time_step_factor: f64 = Kind::Real { default: 0.3, min: 0.0, max: 1.0, min_open: true, max_open: false }, vr 24, unit "1";
            "Safety factor applied to the time-step limits (Fang 2006 eqs. 51-53); under isph the coefficient of King & Lind eq. (28) is 2/3 of it (the default 0.3 gives their 0.2)",
        smoothing_ratio: f64 = real(1.5, 1.0, 3.0), vr 25, unit "1";
            "Smoothing length over particle spacing h/dx. Ignored under isph, which uses King & Lind's quintic kernel with h = 1.3 dx",
        conformation_method: ConformationMethod = enumeration::<ConformationMethod>("ConformationMethod", "auto"), vr 26, unit "";
            "How the conformation tensor is integrated; auto = direct under wcsph and pdri, log-conformation under isph",
        evss_alpha: f64 = real(0.0, 0.0, 1.0), vr 27, unit "1";
            "EVSS added viscosity alpha_V / (1 - beta) scale (King & Lind eqs. 6-8); 0 = off",
        artificial_stress_kind: ArtificialStressKind = enumeration::<ArtificialStressKind>("ArtificialStress", "fang"), vr 28, unit "";
            "Which artificial stress counters the tensile instability",
        artificial_stress_b: f64 = real(0.8, 0.0, 10.0), vr 29, unit "1";
            "Coefficient b of Ren's artificial stress (Ren 2015 eq. 20b). Ignored under isph",
        density_reinit_interval: i64 = integer(20, 0, 1_000_000), vr 30, unit "";
            "PDRI: steps between density reinitialisations (0 = never). Ignored under isph",
        equation_of_state: EquationOfState = enumeration::<EquationOfState>("EquationOfState", "linear"), vr 31, unit "";
            "Equation of state relating pressure to density. Ignored under isph",
        fracture_void_fraction: f64 = real(0.02, 0.0, 1.0), vr 32, unit "1";
            "Health: fraction of the fluid's area torn open into holes beyond which the run stops with a tensile-instability fracture (0 = never check)",
        max_steps_per_do_step: i64 = integer(1_000_000, 1, i32::MAX as i64), vr 33, unit "";
            "FMU: most solver steps one fmi2DoStep may take; past it the call ends in fmi2Discard at the last step reached (fmi2LastSuccessfulTime), which fmi2GetFMUstate/fmi2SetFMUstate continue from. Bounds every call whatever the step size. The CLI bounds a run by its 10^8-step estimate and Ctrl-C instead",
        max_seconds_per_do_step: f64 = real(0.0, 0.0, 1.0e6), vr 34, unit "s";
            "FMU: most wall-clock seconds one fmi2DoStep may take, checked before every solver step, ending like max_steps_per_do_step; 0 = no wall-clock limit. A result then depends on the machine's speed, hence off by default",
        threads: i64 = integer(0, 0, 1024), vr 40, unit "";
            "Worker threads of this simulation's own thread pool; 0 = the RAYON_NUM_THREADS environment variable, else one per core. Results do not depend on it",
        viscous_operator: ViscousOperator = enumeration::<ViscousOperator>("ViscousOperator", "auto"), vr 44, unit "";
            "Weakly compressible schemes: the solvent viscosity inside the stress (Fang's nested operator) or through Morris' Laplacian, which keeps shear layers at walls free of particle-scale zigzag",
        isph_frame: IsphFrame = enumeration::<IsphFrame>("IsphFrame", "lagrangian"), vr 49, unit "";
            "ISPH: Lagrangian particles with shifting, or Eulerian (fixed particles; only for domains without a free surface)",
        isph_viscous_step: ViscousStep = enumeration::<ViscousStep>("ViscousStep", "implicit"), vr 50, unit "";
            "ISPH: solvent viscosity implicit (the time step is then set by the flow speed and the polymer) or explicit as in King & Lind eq. (24)",
        isph_free_surface: IsphFreeSurface = enumeration::<IsphFreeSurface>("IsphFreeSurface", "auto"), vr 51, unit "";
            "ISPH: free-surface pressure; normal_stress = King & Lind eq. (35a)'s solvent normal stress with a pressure gradient consistent with it (the jet buckles), zero_pressure = p = 0 (the drop keeps its volume best); auto = normal_stress in the jet scene, zero_pressure elsewhere",
        wall_boundary: WallBoundary = enumeration::<WallBoundary>("WallBoundary", "auto"), vr 61, unit "";
            "Wall model: image (Fang 2006) or ghost (Ren 2015) particles on straight walls, dummy particles (Adami et al. 2012) for the weakly compressible schemes on any wall, mirror particles (King & Lind 2021) for isph on any wall; auto = the scheme's paper's model on straight walls, dummy (wcsph, pdri) or mirror (isph) on curved ones",
    }
}
