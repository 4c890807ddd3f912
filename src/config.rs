//! Scene configuration: the one table of parameters shared by the FMU, the CLI and the examples.
//!
//! Every parameter the solver accepts is a row of [`PARAMS`]: its FMU name (which is also its
//! scene-file key), value reference, type, default, allowed range, unit and description.
//! Range checks happen here and nowhere else: [`SceneConfig::set`] refuses a value outside the row's
//! range with a message naming the variable, the value and the range, and
//! [`SceneConfig::validate`] adds the checks that involve several parameters (a drop that starts
//! inside the plate, a resolution that would not fit in memory, a model not yet implemented).
//! `modelDescription/modelDescription.xml` is checked against this table by a test, so the FMU's
//! interface and the solver cannot drift apart.

use crate::rheology::{
    AnyRheology, Cross, FeneCr, FeneP, Giesekus, Newtonian, OldroydB, PttExponential, PttLinear,
};
pub use crate::rheology::{ConformationMethod, CONFORMATION_METHODS};
use serde::{Deserialize, Serialize};
use std::fmt;
use thiserror::Error;

/// What went wrong with a parameter. The message names the variable, the value and what is allowed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    #[error("unknown parameter '{0}'")]
    Unknown(String),
    #[error("parameter '{name}' = {value} is outside the allowed range {range}")]
    OutOfRange {
        name: String,
        value: String,
        range: String,
    },
    #[error("parameter '{name}' has a value of the wrong type: {detail}")]
    WrongType { name: String, detail: String },
    #[error("parameter '{name}': '{value}' is not one of {allowed}")]
    BadChoice {
        name: String,
        value: String,
        allowed: String,
    },
    #[error("{0}")]
    Inconsistent(String),
    #[error("scene file: {0}")]
    Parse(String),
}

/// The type of one parameter, with its default and limits.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A real number in `[min, max]`; `min_open`/`max_open` make an end exclusive.
    Real {
        default: f64,
        min: f64,
        max: f64,
        min_open: bool,
        max_open: bool,
    },
    /// An integer in `[min, max]`.
    Integer { default: i64, min: i64, max: i64 },
    /// One of `items`, numbered 1.. in the FMU (FMI 2.0 Enumeration).
    Enumeration {
        type_name: &'static str,
        items: &'static [(&'static str, &'static str)],
        default: &'static str,
    },
}

/// One row of the parameter table.
#[derive(Debug, Clone, Copy)]
pub struct ParamSpec {
    pub name: &'static str,
    pub value_reference: u32,
    pub kind: Kind,
    /// SI unit name as used in the FMU's unitDefinitions ("" for dimensionless).
    pub unit: &'static str,
    pub description: &'static str,
}

const fn real(default: f64, min: f64, max: f64) -> Kind {
    Kind::Real {
        default,
        min,
        max,
        min_open: false,
        max_open: false,
    }
}
const fn real_pos(default: f64, max: f64) -> Kind {
    Kind::Real {
        default,
        min: 0.0,
        max,
        min_open: true,
        max_open: false,
    }
}

pub const SCENES: &[(&str, &str)] = &[
    ("drop", "2D drop falling onto a straight rigid plate"),
    ("jet", "buckling jet from a nozzle onto a plate"),
    (
        "channel",
        "start-up of plane Poiseuille flow between two walls, periodic along the flow (Waters & King 1970)",
    ),
    (
        "elliptical_drop",
        "Monaghan's rotating-stretching elliptical drop, no walls (Ren 2015 section 4.1)",
    ),
];
pub const SCHEMES: &[(&str, &str)] = &[
    ("wcsph", "weakly compressible SPH of Fang et al. 2006"),
    (
        "pdri",
        "SPH with periodic density reinitialisation of Ren et al. 2015",
    ),
    ("isph", "incompressible SPH of King & Lind 2021"),
];
pub const RHEOLOGIES: &[(&str, &str)] = &[
    ("newtonian", "Newtonian fluid"),
    ("oldroyd_b", "Oldroyd-B"),
    ("ucm", "upper-convected Maxwell (Oldroyd-B with no solvent)"),
    ("fene_p", "FENE-P"),
    ("fene_cr", "FENE-CR"),
    ("ptt_linear", "linear Phan-Thien-Tanner"),
    ("ptt_exponential", "exponential Phan-Thien-Tanner"),
    ("giesekus", "Giesekus"),
    ("cross", "Cross shear-thinning generalized Newtonian"),
];
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

/// The parameter table: the single source of names, value references, defaults and ranges.
/// Defaults are Fang et al. 2006's Oldroyd-B drop (D = 2 cm, V = 1 m/s, nu = 0.004 m2/s,
/// lambda1 = 0.02 s, lambda2 = 0.002 s, so beta = lambda2/lambda1 = 0.1), except the sound speed,
/// which is automatic ([`SceneConfig::resolved_sound_speed`]: 12.60 m/s for this drop, Fang's
/// 12.5 m/s within 1 %).
pub const PARAMS: &[ParamSpec] = &[
    ParamSpec { name: "scene", value_reference: 1, kind: Kind::Enumeration { type_name: "Scene", items: SCENES, default: "drop" }, unit: "", description: "Which flow to simulate" },
    ParamSpec { name: "scheme", value_reference: 2, kind: Kind::Enumeration { type_name: "Scheme", items: SCHEMES, default: "wcsph" }, unit: "", description: "SPH scheme" },
    ParamSpec { name: "rheology", value_reference: 3, kind: Kind::Enumeration { type_name: "Rheology", items: RHEOLOGIES, default: "oldroyd_b" }, unit: "", description: "Constitutive model of the fluid" },
    ParamSpec { name: "plate_inclination", value_reference: 4, kind: Kind::Real { default: 0.0, min: 0.0, max: 90.0, min_open: false, max_open: true }, unit: "deg", description: "Angle of the plate to the horizontal; the plate runs downhill towards +x" },
    ParamSpec { name: "impact_velocity", value_reference: 5, kind: real(1.0, 0.0, 100.0), unit: "m/s", description: "Initial speed of the drop, vertically down" },
    ParamSpec { name: "drop_diameter", value_reference: 6, kind: real_pos(0.02, 10.0), unit: "m", description: "Diameter of the initial (circular) drop" },
    ParamSpec { name: "initial_drop_height", value_reference: 7, kind: real_pos(0.04, 100.0), unit: "m", description: "Height of the drop centre above the impact point at t = 0, measured vertically (scene files may also call it drop_height)" },
    ParamSpec { name: "density", value_reference: 8, kind: real_pos(1000.0, 1.0e5), unit: "kg/m3", description: "Reference density rho0" },
    ParamSpec { name: "gravity", value_reference: 9, kind: real(9.81, 0.0, 1000.0), unit: "m/s2", description: "Gravitational acceleration, vertically down" },
    ParamSpec { name: "viscosity", value_reference: 10, kind: real_pos(4.0, 1.0e6), unit: "Pa.s", description: "Total zero-shear viscosity eta0 (solvent + polymer)" },
    ParamSpec { name: "viscosity_ratio", value_reference: 11, kind: real(0.1, 0.0, 1.0), unit: "1", description: "Solvent to total viscosity beta = eta_s/eta0 (Fang's lambda2/lambda1)" },
    ParamSpec { name: "relaxation_time", value_reference: 12, kind: real_pos(0.02, 1.0e6), unit: "s", description: "Polymer relaxation time lambda (Fang's lambda1)" },
    ParamSpec { name: "fene_L2", value_reference: 13, kind: Kind::Real { default: 100.0, min: 2.0, max: 1.0e12, min_open: true, max_open: false }, unit: "1", description: "FENE extensibility L^2 (> 2 in 2D)" },
    ParamSpec { name: "ptt_epsilon", value_reference: 14, kind: real(0.25, 0.0, 10.0), unit: "1", description: "PTT extensibility parameter epsilon" },
    ParamSpec { name: "giesekus_alpha", value_reference: 15, kind: real(0.1, 0.0, 0.5), unit: "1", description: "Giesekus mobility alpha (0 <= alpha <= 0.5)" },
    ParamSpec { name: "cross_viscosity_inf", value_reference: 16, kind: real(0.4, 0.0, 1.0e6), unit: "Pa.s", description: "Cross model infinite-shear viscosity (Ren 2015 eq. 5)" },
    ParamSpec { name: "cross_K", value_reference: 17, kind: real(1.0, 0.0, 1.0e6), unit: "s", description: "Cross model time constant K (Ren 2015 eq. 5)" },
    ParamSpec { name: "cross_m", value_reference: 18, kind: real(1.0, 0.0, 10.0), unit: "1", description: "Cross model exponent m (Ren 2015 eq. 5)" },
    ParamSpec { name: "particles_per_diameter", value_reference: 19, kind: Kind::Integer { default: 20, min: 4, max: 4000 }, unit: "", description: "Resolution: lattice spacing dx = drop_diameter / particles_per_diameter" },
    ParamSpec { name: "sound_speed", value_reference: 20, kind: real(0.0, 0.0, 1.0e5), unit: "m/s", description: "Artificial speed of sound c in the equation of state; 0 = automatic: 10 times the largest speed the scene can reach (impact speed plus free fall), for about 1 % density variation. Ignored under isph (incompressible: no equation of state)" },
    ParamSpec { name: "artificial_viscosity_alpha", value_reference: 21, kind: real(1.0, 0.0, 10.0), unit: "1", description: "Monaghan artificial viscosity alpha (Fang 2006 eq. 31). Ignored under isph" },
    ParamSpec { name: "artificial_viscosity_beta", value_reference: 22, kind: real(2.0, 0.0, 10.0), unit: "1", description: "Monaghan artificial viscosity beta (Fang 2006 eq. 31). Ignored under isph" },
    ParamSpec { name: "artificial_stress_epsilon", value_reference: 23, kind: real(0.5, 0.0, 1.0), unit: "1", description: "Artificial stress epsilon against the tensile instability (Fang 2006 eq. 42); 0 switches it off. Ignored under isph (no tensile instability to counter)" },
    ParamSpec { name: "time_step_factor", value_reference: 24, kind: Kind::Real { default: 0.3, min: 0.0, max: 1.0, min_open: true, max_open: false }, unit: "1", description: "Safety factor applied to the time-step limits (Fang 2006 eqs. 51-53); under isph the coefficient of King & Lind eq. (28) is 2/3 of it (the default 0.3 gives their 0.2)" },
    ParamSpec { name: "smoothing_ratio", value_reference: 25, kind: real(1.5, 1.0, 3.0), unit: "1", description: "Smoothing length over particle spacing h/dx. Ignored under isph, which uses King & Lind's quintic kernel with h = 1.3 dx" },
    ParamSpec { name: "conformation_method", value_reference: 26, kind: Kind::Enumeration { type_name: "ConformationMethod", items: CONFORMATION_METHODS, default: "auto" }, unit: "", description: "How the conformation tensor is integrated; auto = direct under wcsph and pdri, log-conformation under isph" },
    ParamSpec { name: "evss_alpha", value_reference: 27, kind: real(0.0, 0.0, 1.0), unit: "1", description: "EVSS added viscosity alpha_V / (1 - beta) scale (King & Lind eqs. 6-8); 0 = off" },
    ParamSpec { name: "artificial_stress_kind", value_reference: 28, kind: Kind::Enumeration { type_name: "ArtificialStress", items: ARTIFICIAL_STRESS_KINDS, default: "fang" }, unit: "", description: "Which artificial stress counters the tensile instability" },
    ParamSpec { name: "artificial_stress_b", value_reference: 29, kind: real(0.8, 0.0, 10.0), unit: "1", description: "Coefficient b of Ren's artificial stress (Ren 2015 eq. 20b). Ignored under isph" },
    ParamSpec { name: "density_reinit_interval", value_reference: 30, kind: Kind::Integer { default: 20, min: 0, max: 1_000_000 }, unit: "", description: "PDRI: steps between density reinitialisations (0 = never). Ignored under isph" },
    ParamSpec { name: "equation_of_state", value_reference: 31, kind: Kind::Enumeration { type_name: "EquationOfState", items: EQUATIONS_OF_STATE, default: "linear" }, unit: "", description: "Equation of state relating pressure to density. Ignored under isph" },
    ParamSpec { name: "fracture_void_fraction", value_reference: 32, kind: real(0.02, 0.0, 1.0), unit: "1", description: "Health: fraction of the fluid's area torn open into holes beyond which the run stops with a tensile-instability fracture (0 = never check)" },
    ParamSpec { name: "threads", value_reference: 40, kind: Kind::Integer { default: 0, min: 0, max: 1024 }, unit: "", description: "Worker threads of this simulation's own thread pool; 0 = the RAYON_NUM_THREADS environment variable, else one per core. Results do not depend on it" },
    ParamSpec { name: "channel_width", value_reference: 41, kind: real_pos(0.02, 100.0), unit: "m", description: "Channel scene: distance H between the two walls; particles_per_diameter counts particles across it" },
    ParamSpec { name: "channel_length", value_reference: 42, kind: real(0.0, 0.0, 1000.0), unit: "m", description: "Channel scene: period along the flow (rounded to whole particle spacings); 0 = channel_width" },
    ParamSpec { name: "body_force", value_reference: 43, kind: real(80.0, 0.0, 1.0e6), unit: "m/s2", description: "Channel scene: body force per unit mass along the channel, switched on at t = 0 (gravity is off in the channel)" },
    ParamSpec { name: "plate_velocity", value_reference: 60, kind: real(0.0, -1000.0, 1000.0), unit: "m/s", description: "Input: velocity of the plate along its normal, positive away from the fluid; the plate moves rigidly and the walls follow. A co-simulation master may change it at every communication point; this is its start value" },
    ParamSpec { name: "viscous_operator", value_reference: 44, kind: Kind::Enumeration { type_name: "ViscousOperator", items: VISCOUS_OPERATORS, default: "auto" }, unit: "", description: "Weakly compressible schemes: the solvent viscosity inside the stress (Fang's nested operator) or through Morris' Laplacian, which keeps shear layers at walls free of particle-scale zigzag" },
    ParamSpec { name: "jet_width", value_reference: 45, kind: real_pos(0.006, 10.0), unit: "m", description: "Jet scene: width D of the planar jet at the nozzle exit (King & Lind 2021: 6 mm); particles_per_diameter counts particles across it" },
    ParamSpec { name: "nozzle_height", value_reference: 46, kind: real_pos(0.072, 100.0), unit: "m", description: "Jet scene: height of the nozzle exit above the impact point, measured vertically (King & Lind 2021: 12 D)" },
    ParamSpec { name: "jet_velocity", value_reference: 47, kind: real(0.2, 0.0, 100.0), unit: "m/s", description: "Input: jet scene: speed of the fluid leaving the nozzle, vertically down (King & Lind 2021: 0.2 m/s). A co-simulation master (a pump or valve model) may change it at every communication point; this is its start value, which also sets the automatic sound speed" },
    ParamSpec { name: "container_width", value_reference: 48, kind: real(0.0, 0.0, 100.0), unit: "m", description: "Jet scene: distance between the container's side walls, centred on the impact point and perpendicular to the plate; 0 = no side walls" },
    ParamSpec { name: "isph_frame", value_reference: 49, kind: Kind::Enumeration { type_name: "IsphFrame", items: ISPH_FRAMES, default: "lagrangian" }, unit: "", description: "ISPH: Lagrangian particles with shifting, or Eulerian (fixed particles; only for domains without a free surface)" },
    ParamSpec { name: "isph_viscous_step", value_reference: 50, kind: Kind::Enumeration { type_name: "ViscousStep", items: VISCOUS_STEPS, default: "implicit" }, unit: "", description: "ISPH: solvent viscosity implicit (the time step is then set by the flow speed and the polymer) or explicit as in King & Lind eq. (24)" },
    ParamSpec { name: "isph_free_surface", value_reference: 51, kind: Kind::Enumeration { type_name: "IsphFreeSurface", items: ISPH_FREE_SURFACES, default: "auto" }, unit: "", description: "ISPH: free-surface pressure; normal_stress = King & Lind eq. (35a)'s solvent normal stress with a pressure gradient consistent with it (the jet buckles), zero_pressure = p = 0 (the drop keeps its volume best); auto = normal_stress in the jet scene, zero_pressure elsewhere" },
];

/// The rheology is built here, next to the table that names its parameters, so that the
/// constitutive models (`crate::rheology`) depend on nothing above them.
impl AnyRheology {
    /// Build the configured model from `viscosity` (eta0, total zero-shear), `viscosity_ratio`
    /// (beta = eta_s/eta0), `relaxation_time` (lambda) and the model's own parameter. UCM is
    /// Oldroyd-B with beta = 0 whatever `viscosity_ratio` says; Newtonian and Cross ignore
    /// beta and lambda (the whole viscosity is the solvent's). Parameter ranges were checked by
    /// the parameter table (`config::PARAMS`).
    pub fn from_config(cfg: &SceneConfig) -> Result<Self, ConfigError> {
        let eta0 = cfg.viscosity;
        let beta = cfg.viscosity_ratio;
        let lambda = cfg.relaxation_time;
        Ok(match cfg.rheology {
            RheologyKind::Newtonian => AnyRheology::Newtonian(Newtonian::new(eta0)),
            RheologyKind::OldroydB => AnyRheology::OldroydB(OldroydB::new(eta0, beta, lambda)),
            RheologyKind::Ucm => AnyRheology::OldroydB(OldroydB::new(eta0, 0.0, lambda)),
            RheologyKind::FeneP => AnyRheology::FeneP(FeneP::new(eta0, beta, lambda, cfg.fene_L2)),
            RheologyKind::FeneCr => {
                AnyRheology::FeneCr(FeneCr::new(eta0, beta, lambda, cfg.fene_L2))
            }
            RheologyKind::PttLinear => {
                AnyRheology::PttLinear(PttLinear::new(eta0, beta, lambda, cfg.ptt_epsilon))
            }
            RheologyKind::PttExponential => AnyRheology::PttExponential(PttExponential::new(
                eta0,
                beta,
                lambda,
                cfg.ptt_epsilon,
            )),
            RheologyKind::Giesekus => {
                AnyRheology::Giesekus(Giesekus::new(eta0, beta, lambda, cfg.giesekus_alpha))
            }
            RheologyKind::Cross => AnyRheology::Cross(Cross::new(
                eta0,
                cfg.cross_viscosity_inf,
                cfg.cross_K,
                cfg.cross_m,
            )),
        })
    }
}

/// Index of a parameter in [`PARAMS`] by name.
/// `drop_height` is accepted as the older name of `initial_drop_height`: the FMU needs unique
/// variable names and `drop_height` is an output.
pub fn param_spec(name: &str) -> Option<&'static ParamSpec> {
    let name = if name == "drop_height" {
        "initial_drop_height"
    } else {
        name
    };
    PARAMS.iter().find(|p| p.name == name)
}

/// The parameter with a given FMU value reference.
pub fn param_by_vr(vr: u32) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|p| p.value_reference == vr)
}

/// The rows of [`PARAMS`] that are FMU *inputs* (causality "input", variability "continuous")
/// rather than fixed parameters: a co-simulation master may set them again after
/// initialization, at every communication point (FMI 2.0 section 2.2.7, and section 4.2.4 for
/// Co-Simulation). Their table row gives the start value, the range and the scene-file key, so
/// a scene file sets an input's start value by its name like any parameter. In the running
/// simulation they live in [`crate::state::Inputs`].
pub const INPUT_NAMES: &[&str] = &["plate_velocity", "jet_velocity"];

impl ParamSpec {
    /// Whether this row is an input (see [`INPUT_NAMES`]).
    pub fn is_input(&self) -> bool {
        INPUT_NAMES.contains(&self.name)
    }
}

/// Value reference of an enumeration's String twin: the enumeration's own plus this offset, so
/// every variable of the FMU has a value reference of its own, whatever its type.
pub const NAME_VR_OFFSET: u32 = 1000;

/// Suffix of the String twins' names: `rheology` is also settable as `rheology_name`.
pub const NAME_SUFFIX: &str = "_name";

/// The String twin of each Enumeration row: `(row, twin name, twin value reference)`.
///
/// Why twins exist: OSP's libcosim and ecos ignore FMI 2.0 Enumeration variables (they warn
/// "variable type not supported" and leave the default), and fmpy's `simulate_fmu` converts an
/// Enumeration's start value with `int()`, so a model could be chosen there only by item number.
/// All of them, and fmi-sim, set String variables by name. The Enumeration stays the canonical
/// variable (same name and value reference as before, shown as a list of items by tools that
/// read TypeDefinitions); its twin sets the same parameter, and the last value set wins.
/// Not an Integer alias of the Enumeration (Integer and Enumeration share one value-reference
/// space): that would put two parameters, each with the start value a parameter needs, in one
/// alias set, which FMI 2.0 section 2.2.7 forbids ("at most one variable of the same alias set
/// of variables with variability != constant can have a start attribute"), and it would still
/// take only numbers.
pub fn name_variables() -> impl Iterator<Item = (&'static ParamSpec, String, u32)> {
    PARAMS.iter().filter_map(|p| match p.kind {
        Kind::Enumeration { .. } => Some((
            p,
            format!("{}{NAME_SUFFIX}", p.name),
            p.value_reference + NAME_VR_OFFSET,
        )),
        _ => None,
    })
}

/// The Enumeration row whose String twin has value reference `vr`.
pub fn name_variable_by_vr(vr: u32) -> Option<&'static ParamSpec> {
    name_variables()
        .find(|(_, _, v)| *v == vr)
        .map(|(p, _, _)| p)
}

/// The Enumeration row whose String twin is called `name` (e.g. `rheology_name`).
pub fn name_variable(name: &str) -> Option<&'static ParamSpec> {
    let stem = name.strip_suffix(NAME_SUFFIX)?;
    PARAMS
        .iter()
        .find(|p| p.name == stem && matches!(p.kind, Kind::Enumeration { .. }))
}

crate::choice_enum!(
    /// The flow to simulate.
    Scene, SCENES, Drop = "drop", Jet = "jet", EllipticalDrop = "elliptical_drop", Channel = "channel");
crate::choice_enum!(
    /// The SPH scheme.
    SchemeKind, SCHEMES, Wcsph = "wcsph", Pdri = "pdri", Isph = "isph");
crate::choice_enum!(
    /// The constitutive model.
    RheologyKind, RHEOLOGIES,
    Newtonian = "newtonian", OldroydB = "oldroyd_b", Ucm = "ucm", FeneP = "fene_p",
    FeneCr = "fene_cr", PttLinear = "ptt_linear", PttExponential = "ptt_exponential",
    Giesekus = "giesekus", Cross = "cross");
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
crate::choice_enum!(
    /// How the solvent's viscous force is discretised.
    ViscousOperator, VISCOUS_OPERATORS, Auto = "auto", Nested = "nested", Laplacian = "laplacian");

/// A parameter value as it arrives from a scene file or the FMU.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i64),
    Text(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Real(x) => write!(f, "{x}"),
            Value::Integer(i) => write!(f, "{i}"),
            Value::Text(s) => write!(f, "'{s}'"),
        }
    }
}

/// Everything that defines a simulation. Field names are the FMU parameter names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct SceneConfig {
    pub scene: Scene,
    pub scheme: SchemeKind,
    pub rheology: RheologyKind,
    pub plate_inclination: f64,
    pub impact_velocity: f64,
    pub drop_diameter: f64,
    /// FMU name `initial_drop_height` (`drop_height` is an output).
    pub drop_height: f64,
    pub density: f64,
    pub gravity: f64,
    pub viscosity: f64,
    pub viscosity_ratio: f64,
    pub relaxation_time: f64,
    pub fene_L2: f64,
    pub ptt_epsilon: f64,
    pub giesekus_alpha: f64,
    pub cross_viscosity_inf: f64,
    pub cross_K: f64,
    pub cross_m: f64,
    pub particles_per_diameter: i64,
    pub sound_speed: f64,
    pub artificial_viscosity_alpha: f64,
    pub artificial_viscosity_beta: f64,
    pub artificial_stress_epsilon: f64,
    pub time_step_factor: f64,
    pub smoothing_ratio: f64,
    pub conformation_method: ConformationMethod,
    pub evss_alpha: f64,
    pub artificial_stress_kind: ArtificialStressKind,
    pub artificial_stress_b: f64,
    pub density_reinit_interval: i64,
    pub equation_of_state: EquationOfState,
    pub fracture_void_fraction: f64,
    /// Size of the simulation's own thread pool (0 = RAYON_NUM_THREADS or one per core).
    pub threads: i64,
    pub channel_width: f64,
    pub channel_length: f64,
    pub body_force: f64,
    pub viscous_operator: ViscousOperator,
    pub jet_width: f64,
    pub nozzle_height: f64,
    pub jet_velocity: f64,
    pub container_width: f64,
    /// Start value of the input `plate_velocity` (see [`INPUT_NAMES`]).
    pub plate_velocity: f64,
    pub isph_frame: IsphFrame,
    pub isph_viscous_step: ViscousStep,
    pub isph_free_surface: IsphFreeSurface,
}

/// Automatic sound speed over the largest expected flow speed: 10 for about 1 % density
/// variation (see [`SceneConfig::resolved_sound_speed`]).
pub const SOUND_SPEED_FACTOR: f64 = 10.0;

/// Largest number of particles (fluid + wall) a scene may ask for: about 2 GB of state.
pub const MAX_PARTICLES: f64 = 5.0e6;

impl Default for SceneConfig {
    fn default() -> Self {
        let mut c = SceneConfig {
            scene: Scene::Drop,
            scheme: SchemeKind::Wcsph,
            rheology: RheologyKind::OldroydB,
            plate_inclination: 0.0,
            impact_velocity: 0.0,
            drop_diameter: 0.0,
            drop_height: 0.0,
            density: 0.0,
            gravity: 0.0,
            viscosity: 0.0,
            viscosity_ratio: 0.0,
            relaxation_time: 0.0,
            fene_L2: 0.0,
            ptt_epsilon: 0.0,
            giesekus_alpha: 0.0,
            cross_viscosity_inf: 0.0,
            cross_K: 0.0,
            cross_m: 0.0,
            particles_per_diameter: 0,
            sound_speed: 0.0,
            artificial_viscosity_alpha: 0.0,
            artificial_viscosity_beta: 0.0,
            artificial_stress_epsilon: 0.0,
            time_step_factor: 0.0,
            smoothing_ratio: 0.0,
            conformation_method: ConformationMethod::Direct,
            evss_alpha: 0.0,
            artificial_stress_kind: ArtificialStressKind::Fang,
            artificial_stress_b: 0.0,
            density_reinit_interval: 0,
            equation_of_state: EquationOfState::Linear,
            fracture_void_fraction: 0.0,
            threads: 0,
            channel_width: 0.0,
            channel_length: 0.0,
            body_force: 0.0,
            viscous_operator: ViscousOperator::Auto,
            jet_width: 0.0,
            nozzle_height: 0.0,
            jet_velocity: 0.0,
            container_width: 0.0,
            plate_velocity: 0.0,
            isph_frame: IsphFrame::Lagrangian,
            isph_viscous_step: ViscousStep::Implicit,
            isph_free_surface: IsphFreeSurface::Auto,
        };
        for p in PARAMS {
            let v = match p.kind {
                Kind::Real { default, .. } => Value::Real(default),
                Kind::Integer { default, .. } => Value::Integer(default),
                Kind::Enumeration { default, .. } => Value::Text(default.to_string()),
            };
            c.set(p.name, v).expect("table defaults are valid");
        }
        c
    }
}

impl SceneConfig {
    /// Set one parameter by its FMU name, checking type and range against [`PARAMS`].
    /// Enumerations accept their name (`Value::Text`) or their 1-based index (`Value::Integer`).
    /// A String twin (`rheology_name`, see [`name_variables`]) takes an item name.
    pub fn set(&mut self, name: &str, value: Value) -> Result<(), ConfigError> {
        if param_spec(name).is_none() {
            if let Some(p) = name_variable(name) {
                return match value {
                    Value::Text(_) => self.set(p.name, value),
                    other => Err(ConfigError::WrongType {
                        name: name.into(),
                        detail: format!(
                            "expected one of the names {}, got {other}",
                            range_text(&p.kind)
                        ),
                    }),
                };
            }
        }
        let spec = param_spec(name).ok_or_else(|| ConfigError::Unknown(name.to_string()))?;
        match spec.kind {
            Kind::Real {
                min,
                max,
                min_open,
                max_open,
                ..
            } => {
                let x = match value {
                    Value::Real(x) => x,
                    Value::Integer(i) => i as f64,
                    Value::Text(ref s) => {
                        return Err(ConfigError::WrongType {
                            name: name.into(),
                            detail: format!("expected a real number, got '{s}'"),
                        })
                    }
                };
                let lo_ok = if min_open { x > min } else { x >= min };
                let hi_ok = if max_open { x < max } else { x <= max };
                if !x.is_finite() || !lo_ok || !hi_ok {
                    return Err(ConfigError::OutOfRange {
                        name: name.into(),
                        value: format!("{x}"),
                        range: range_text(&spec.kind),
                    });
                }
                *self.real_field(name).expect("every Real row has a field") = x;
            }
            Kind::Integer { min, max, .. } => {
                let i = match value {
                    Value::Integer(i) => i,
                    Value::Real(x) if x.fract() == 0.0 && x.is_finite() => x as i64,
                    other => {
                        return Err(ConfigError::WrongType {
                            name: name.into(),
                            detail: format!("expected an integer, got {other}"),
                        })
                    }
                };
                if i < min || i > max {
                    return Err(ConfigError::OutOfRange {
                        name: name.into(),
                        value: format!("{i}"),
                        range: range_text(&spec.kind),
                    });
                }
                match name {
                    "particles_per_diameter" => self.particles_per_diameter = i,
                    "density_reinit_interval" => self.density_reinit_interval = i,
                    "threads" => self.threads = i,
                    _ => unreachable!("integer row without field: {name}"),
                }
            }
            Kind::Enumeration { items, .. } => {
                let text = match value {
                    Value::Text(s) => s,
                    Value::Integer(i) if i >= 1 && (i as usize) <= items.len() => {
                        items[(i - 1) as usize].0.to_string()
                    }
                    other => {
                        return Err(ConfigError::BadChoice {
                            name: name.into(),
                            value: other.to_string(),
                            allowed: choices_text(items),
                        })
                    }
                };
                let bad = || ConfigError::BadChoice {
                    name: name.into(),
                    value: text.clone(),
                    allowed: choices_text(items),
                };
                match name {
                    "scene" => self.scene = Scene::parse(&text).ok_or_else(bad)?,
                    "scheme" => self.scheme = SchemeKind::parse(&text).ok_or_else(bad)?,
                    "rheology" => self.rheology = RheologyKind::parse(&text).ok_or_else(bad)?,
                    "conformation_method" => {
                        self.conformation_method =
                            ConformationMethod::parse(&text).ok_or_else(bad)?
                    }
                    "artificial_stress_kind" => {
                        self.artificial_stress_kind =
                            ArtificialStressKind::parse(&text).ok_or_else(bad)?
                    }
                    "equation_of_state" => {
                        self.equation_of_state = EquationOfState::parse(&text).ok_or_else(bad)?
                    }
                    "viscous_operator" => {
                        self.viscous_operator = ViscousOperator::parse(&text).ok_or_else(bad)?
                    }
                    "isph_frame" => self.isph_frame = IsphFrame::parse(&text).ok_or_else(bad)?,
                    "isph_viscous_step" => {
                        self.isph_viscous_step = ViscousStep::parse(&text).ok_or_else(bad)?
                    }
                    "isph_free_surface" => {
                        self.isph_free_surface = IsphFreeSurface::parse(&text).ok_or_else(bad)?
                    }
                    _ => unreachable!("enumeration row without field: {name}"),
                }
            }
        }
        Ok(())
    }

    /// Current value of a parameter by name (enumerations as their 1-based index).
    pub fn get(&self, name: &str) -> Result<Value, ConfigError> {
        let spec = param_spec(name).ok_or_else(|| ConfigError::Unknown(name.to_string()))?;
        Ok(match spec.kind {
            Kind::Real { .. } => Value::Real(*self.clone().real_field(name).expect("field")),
            Kind::Integer { .. } => Value::Integer(match name {
                "particles_per_diameter" => self.particles_per_diameter,
                "density_reinit_interval" => self.density_reinit_interval,
                "threads" => self.threads,
                _ => unreachable!(),
            }),
            Kind::Enumeration { .. } => Value::Integer(match name {
                "scene" => self.scene.index(),
                "scheme" => self.scheme.index(),
                "rheology" => self.rheology.index(),
                "conformation_method" => self.conformation_method.index(),
                "artificial_stress_kind" => self.artificial_stress_kind.index(),
                "equation_of_state" => self.equation_of_state.index(),
                "viscous_operator" => self.viscous_operator.index(),
                "isph_frame" => self.isph_frame.index(),
                "isph_viscous_step" => self.isph_viscous_step.index(),
                "isph_free_surface" => self.isph_free_surface.index(),
                _ => unreachable!(),
            }),
        })
    }

    /// The item name of an Enumeration parameter (what its String twin reads).
    pub fn item_name(&self, name: &str) -> Result<&'static str, ConfigError> {
        let spec = param_spec(name).ok_or_else(|| ConfigError::Unknown(name.to_string()))?;
        match (spec.kind, self.get(name)?) {
            (Kind::Enumeration { items, .. }, Value::Integer(i)) => Ok(items[(i - 1) as usize].0),
            _ => Err(ConfigError::WrongType {
                name: name.into(),
                detail: "not an enumeration".into(),
            }),
        }
    }

    fn real_field(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "plate_inclination" => &mut self.plate_inclination,
            "impact_velocity" => &mut self.impact_velocity,
            "drop_diameter" => &mut self.drop_diameter,
            "initial_drop_height" | "drop_height" => &mut self.drop_height,
            "density" => &mut self.density,
            "gravity" => &mut self.gravity,
            "viscosity" => &mut self.viscosity,
            "viscosity_ratio" => &mut self.viscosity_ratio,
            "relaxation_time" => &mut self.relaxation_time,
            "fene_L2" => &mut self.fene_L2,
            "ptt_epsilon" => &mut self.ptt_epsilon,
            "giesekus_alpha" => &mut self.giesekus_alpha,
            "cross_viscosity_inf" => &mut self.cross_viscosity_inf,
            "cross_K" => &mut self.cross_K,
            "cross_m" => &mut self.cross_m,
            "sound_speed" => &mut self.sound_speed,
            "artificial_viscosity_alpha" => &mut self.artificial_viscosity_alpha,
            "artificial_viscosity_beta" => &mut self.artificial_viscosity_beta,
            "artificial_stress_epsilon" => &mut self.artificial_stress_epsilon,
            "time_step_factor" => &mut self.time_step_factor,
            "smoothing_ratio" => &mut self.smoothing_ratio,
            "evss_alpha" => &mut self.evss_alpha,
            "artificial_stress_b" => &mut self.artificial_stress_b,
            "fracture_void_fraction" => &mut self.fracture_void_fraction,
            "channel_width" => &mut self.channel_width,
            "channel_length" => &mut self.channel_length,
            "body_force" => &mut self.body_force,
            "jet_width" => &mut self.jet_width,
            "nozzle_height" => &mut self.nozzle_height,
            "jet_velocity" => &mut self.jet_velocity,
            "container_width" => &mut self.container_width,
            "plate_velocity" => &mut self.plate_velocity,
            _ => return None,
        })
    }

    /// The start values of the inputs (see [`INPUT_NAMES`]).
    pub fn inputs(&self) -> crate::state::Inputs {
        crate::state::Inputs {
            plate_velocity: self.plate_velocity,
            jet_velocity: self.jet_velocity,
        }
    }

    /// Particle spacing dx = D / particles_per_diameter (Fang 2006 section 4: a Cartesian lattice).
    pub fn dx(&self) -> f64 {
        self.drop_diameter / self.particles_per_diameter as f64
    }

    /// Smoothing length h = smoothing_ratio * dx (Fang uses h = 1.5 dx).
    pub fn h(&self) -> f64 {
        self.smoothing_ratio * self.dx()
    }

    /// Largest speed the scene's fluid can reach from its initial conditions \[m/s\]: for a drop,
    /// the impact speed plus the free fall from its initial height until its lowest point
    /// touches the plate, sqrt(V^2 + 2 g h_fall); for a jet, the free-fall speed at the plate
    /// sqrt(U0^2 + 2 g H) with U0 = `jet_velocity` and H = `nozzle_height`. A flow that spreads or slides afterwards does not
    /// speed up much beyond it (viscosity and the plate take energy out), which is what makes
    /// it the reference for the sound speed. At least 1 mm/s, so a scene with nothing moving
    /// still gets a finite time step. The elliptical drop fixes its own c (its scene sets it).
    pub fn max_expected_speed(&self) -> f64 {
        let v = self.impact_velocity;
        let fall = match self.scene {
            Scene::Drop => {
                let theta = self.plate_inclination.to_radians();
                (self.drop_height - 0.5 * self.drop_diameter / theta.cos()).max(0.0)
            }
            Scene::Jet => {
                let u0 = self.jet_velocity;
                return (u0 * u0 + 2.0 * self.gravity * self.nozzle_height)
                    .sqrt()
                    .max(1e-3);
            }
            Scene::EllipticalDrop => self.drop_height.max(0.0),
            Scene::Channel => {
                // The steady Newtonian centre-line speed U = rho g H^2 / (8 eta0); an elastic
                // start-up overshoots it (Waters & King 1970: 2.85 U at Re = Wi = 1, more when
                // Wi/Re is large), so elastic models get 3 U. Strongly elastic channels (Wi/Re
                // well above 1) should set sound_speed themselves.
                let u = self.density * self.body_force * self.channel_width.powi(2)
                    / (8.0 * self.viscosity);
                let elastic =
                    !matches!(self.rheology, RheologyKind::Newtonian | RheologyKind::Cross);
                return (if elastic { 3.0 * u } else { u }).max(1e-3);
            }
        };
        (v * v + 2.0 * self.gravity * fall).sqrt().max(1e-3)
    }

    /// The sound speed the run uses \[m/s\]: `sound_speed` when it is set (> 0), otherwise
    /// [`SOUND_SPEED_FACTOR`] times [`SceneConfig::max_expected_speed`]. A weakly compressible
    /// scheme's density varies by about (U/c)^2 (Monaghan 1994; Morris, Fox & Zhu 1997), so
    /// c = 10 U keeps it near 1 %. For Fang 2006's default drop (V = 1 m/s,
    /// 3 cm of free fall) that gives c = 12.60 m/s against Fang's 12.5 m/s.
    pub fn resolved_sound_speed(&self) -> f64 {
        if self.sound_speed > 0.0 {
            self.sound_speed
        } else {
            SOUND_SPEED_FACTOR * self.max_expected_speed()
        }
    }

    /// Checks that involve several parameters, or that the scene can actually be built.
    /// Single-value ranges were already enforced by [`SceneConfig::set`]; they are checked
    /// again here so a config built field by field in Rust is held to the same table.
    ///
    /// The checks that belong to one scene (a drop that starts inside its plate, a scene not
    /// built yet) are the scene's own: `Simulation::validate` runs both.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for p in PARAMS {
            let v = self.get(p.name)?;
            self.clone().set(p.name, v)?;
        }
        let inconsistent = |s: String| Err(ConfigError::Inconsistent(s));
        if self.scheme == SchemeKind::Isph
            && self.isph_frame == IsphFrame::Eulerian
            && self.scene != Scene::Channel
        {
            return inconsistent(format!(
                "isph_frame = 'eulerian' needs a domain without a free surface (scene = 'channel'); \
                 the scene '{}' has one: use isph_frame = 'lagrangian'",
                self.scene
            ));
        }
        if self.rheology == RheologyKind::PttLinear && self.ptt_epsilon > 0.5 {
            return inconsistent(format!(
                "ptt_epsilon = {} is outside [0, 0.5] for the linear PTT model: its relaxation factor \
                 1 + epsilon tr(A - I) would turn negative for a compressed, still positive-definite A",
                self.ptt_epsilon
            ));
        }
        if self.rheology == RheologyKind::Cross && self.cross_viscosity_inf > self.viscosity {
            return inconsistent(format!(
                "cross_viscosity_inf = {} Pa.s exceeds the zero-shear viscosity = {} Pa.s: the Cross \
                 model (Ren 2015 eq. 5) is shear-thinning, so it must be at most viscosity",
                self.cross_viscosity_inf, self.viscosity
            ));
        }
        let ppd = self.particles_per_diameter as f64;
        let estimate = self.estimated_particles();
        if estimate > MAX_PARTICLES {
            return inconsistent(format!(
                "particles_per_diameter = {} would need about {:.2e} particles, more than the {:.0e} that fit in memory",
                self.particles_per_diameter, estimate, MAX_PARTICLES
            ));
        }
        let _ = ppd;
        Ok(())
    }

    /// Rough particle count (fluid + wall) of the scene, for the memory check.
    pub fn estimated_particles(&self) -> f64 {
        let ppd = self.particles_per_diameter as f64;
        let fluid = std::f64::consts::FRAC_PI_4 * ppd * ppd;
        let (fluid, wall) = match self.scene {
            Scene::Drop => (fluid, 4.0 * ppd * 20.0),
            Scene::Channel => {
                let along =
                    (self.channel_length.max(self.channel_width) / self.channel_width) * ppd;
                (ppd * along, 10.0 * along)
            }
            _ => (fluid, 0.0),
        };
        fluid + wall
    }

    /// The defaults of a scene: the table's ([`PARAMS`], Fang's drop) with the scene's own
    /// values over them, for the scenes that have some (the jet: King & Lind's case,
    /// [`JET_DEFAULTS`]). The table stays the one source of names, ranges and
    /// units, and of the FMU's start values (one per variable, so an FMU that is told only
    /// `scene = jet` runs the table's values); scene files start from these.
    pub fn for_scene(scene: Scene) -> Self {
        let mut c = SceneConfig {
            scene,
            ..Default::default()
        };
        let own = match scene {
            Scene::Jet => JET_DEFAULTS,
            _ => "",
        };
        let table: toml::Table = own.parse().expect("a scene's defaults are TOML");
        c.apply_table(table)
            .expect("a scene's defaults are within the table's ranges");
        c
    }

    /// Read a flat TOML scene file whose keys are the FMU parameter names. Missing keys keep
    /// their defaults, those of the scene it names ([`SceneConfig::for_scene`]); an unknown key
    /// or a bad value is an error naming it, and so is a file that gives both
    /// `initial_drop_height` and its older name `drop_height`.
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| ConfigError::Parse(e.to_string()))?;
        if table.contains_key("drop_height") && table.contains_key("initial_drop_height") {
            return Err(ConfigError::Inconsistent(format!(
                "both 'initial_drop_height' ({}) and its older name 'drop_height' ({}) are given: \
                 keep one",
                table["initial_drop_height"], table["drop_height"]
            )));
        }
        let mut cfg = SceneConfig::default();
        if let Some(scene) = table.get("scene").and_then(|v| v.as_str()) {
            // A scene that is not one is reported by `set` below.
            if let Some(scene) = Scene::parse(scene) {
                cfg = SceneConfig::for_scene(scene);
            }
        }
        cfg.apply_table(table)?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Set every key of a flat TOML table.
    fn apply_table(&mut self, table: toml::Table) -> Result<(), ConfigError> {
        for (key, val) in table {
            let v = match val {
                toml::Value::Float(x) => Value::Real(x),
                toml::Value::Integer(i) => Value::Integer(i),
                toml::Value::String(s) => Value::Text(s),
                other => {
                    return Err(ConfigError::WrongType {
                        name: key,
                        detail: format!("unsupported TOML value {other}"),
                    })
                }
            };
            self.set(&key, v)?;
        }
        Ok(())
    }

    /// The scene as a flat TOML file (every parameter, enumerations by name).
    pub fn to_toml_string(&self) -> String {
        let mut s = String::new();
        for p in PARAMS {
            let line = match (p.kind, self.get(p.name).expect("known")) {
                (Kind::Enumeration { items, .. }, Value::Integer(i)) => {
                    format!("{} = \"{}\"", p.name, items[(i - 1) as usize].0)
                }
                (Kind::Real { .. }, Value::Real(x)) => format!("{} = {:?}", p.name, x),
                (_, v) => format!("{} = {}", p.name, v),
            };
            s.push_str(&line);
            s.push('\n');
        }
        s
    }
}

/// Human-readable range of a row, e.g. "[0, 90)".
pub fn range_text(kind: &Kind) -> String {
    match *kind {
        Kind::Real {
            min,
            max,
            min_open,
            max_open,
            ..
        } => format!(
            "{}{}, {}{}",
            if min_open { "(" } else { "[" },
            min,
            max,
            if max_open { ")" } else { "]" }
        ),
        Kind::Integer { min, max, .. } => format!("[{min}, {max}]"),
        Kind::Enumeration { items, .. } => choices_text(items),
    }
}

fn choices_text(items: &[(&str, &str)]) -> String {
    let names: Vec<String> = items.iter().map(|(n, _)| format!("'{n}'")).collect();
    format!("{{{}}}", names.join(", "))
}

/// What a jet gets for the keys a scene file leaves out, over the parameter table's defaults
/// (which are Fang's drop): King & Lind 2021 section IV.D's Oldroyd-B jet, D = 6 mm,
/// U0 = 0.2 m/s, nozzle 12 D above the plate, eta0 = 8.8 Pa s, rho = 1023 kg/m3 (Re = 0.14),
/// beta = 0.2, lambda = 0.05 s (Wi = lambda U0 / D = 5/3), at 6 particles across (King & Lind:
/// 20), about a minute to t* = 8 (0.97 s). Under WCSPH, which buckles from 12 D, reproduces
/// both of King & Lind's arrival trends and reaches the plate within -2 to +8 % of the
/// slender-sheet model (`reference/src/analytic/falling_sheet.rs`). King & Lind's ISPH buckles too
/// (`isph_free_surface = auto`), but at this resolution its column falls 11-14 % early (its
/// implicit viscous step's splitting error), thins to two particles and tears, and with
/// shorter steps its Wi = 5/3 heap breaks down (docs/methods.md, "Why WCSPH and not King &
/// Lind's ISPH").
/// Written as a scene file and read through the table ([`SceneConfig::for_scene`]), so every
/// value is checked against its row's range.
pub const JET_DEFAULTS: &str = "\
scheme = \"wcsph\"
rheology = \"oldroyd_b\"
density = 1023.0
viscosity = 8.8
viscosity_ratio = 0.2
relaxation_time = 0.05
gravity = 9.81
jet_width = 0.006
jet_velocity = 0.2
nozzle_height = 0.072
particles_per_diameter = 6
";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_fang_oldroyd_b() {
        let c = SceneConfig::default();
        assert_eq!(c.rheology, RheologyKind::OldroydB);
        assert_eq!(c.drop_diameter, 0.02);
        assert_eq!(c.viscosity_ratio, 0.1);
        assert_eq!(c.sound_speed, 0.0, "automatic by default");
        c.validate().unwrap();
    }

    #[test]
    fn automatic_sound_speed_follows_the_impact() {
        // Fang's drop: V = 1 m/s, centre 4 cm above the plate, so 3 cm of free fall before the
        // drop touches: U = sqrt(1 + 2 * 9.81 * 0.03) = 1.2604 m/s, c = 12.60 m/s (Fang: 12.5).
        let mut c = SceneConfig::default();
        let u = (1.0f64 + 2.0 * 9.81 * 0.03).sqrt();
        assert!((c.max_expected_speed() - u).abs() < 1e-12);
        assert!((c.resolved_sound_speed() - 10.0 * u).abs() < 1e-12);
        assert!((c.resolved_sound_speed() - 12.5).abs() / 12.5 < 0.01);
        // Five times faster: five times the sound speed, nearly.
        c.impact_velocity = 5.0;
        assert!((c.resolved_sound_speed() - 10.0 * (25.0f64 + 0.5886).sqrt()).abs() < 1e-9);
        // On an inclined plate the drop meets the plate earlier: less free fall.
        c.impact_velocity = 0.0;
        c.plate_inclination = 60.0;
        let fall: f64 = 0.04 - 0.01 / 0.5;
        assert!((c.max_expected_speed() - (2.0 * 9.81 * fall).sqrt()).abs() < 1e-12);
        // An explicit value wins.
        c.sound_speed = 30.0;
        assert_eq!(c.resolved_sound_speed(), 30.0);
    }

    #[test]
    fn out_of_range_names_variable_value_and_range() {
        let mut c = SceneConfig::default();
        let e = c.set("plate_inclination", Value::Real(90.0)).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("plate_inclination") && msg.contains("90") && msg.contains("[0, 90)"),
            "{msg}"
        );
        let e = c
            .set("drop_diameter", Value::Real(-1.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("drop_diameter") && e.contains("-1"), "{e}");
        let e = c
            .set("viscosity_ratio", Value::Real(f64::NAN))
            .unwrap_err()
            .to_string();
        assert!(e.contains("viscosity_ratio") && e.contains("NaN"), "{e}");
        assert!(matches!(
            c.set("nonsense", Value::Real(1.0)),
            Err(ConfigError::Unknown(_))
        ));
    }

    #[test]
    fn toml_round_trip_and_unknown_key() {
        let mut c = SceneConfig::default();
        c.set("rheology", Value::Text("newtonian".into())).unwrap();
        c.set("plate_inclination", Value::Real(30.0)).unwrap();
        let back = SceneConfig::from_toml_str(&c.to_toml_string()).unwrap();
        assert_eq!(back, c);
        let e = SceneConfig::from_toml_str("drop_diametr = 0.1")
            .unwrap_err()
            .to_string();
        assert!(e.contains("drop_diametr"), "{e}");
        let e = SceneConfig::from_toml_str("rheology = \"honey\"")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("rheology") && e.contains("honey") && e.contains("oldroyd_b"),
            "{e}"
        );
    }

    #[test]
    fn both_names_of_the_drop_height_are_refused() {
        let c = SceneConfig::from_toml_str("drop_height = 0.05\n").unwrap();
        assert_eq!(c.drop_height, 0.05, "the older name still works alone");
        let e = SceneConfig::from_toml_str("drop_height = 0.05\ninitial_drop_height = 0.06\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("drop_height") && e.contains("initial_drop_height") && e.contains("0.05"),
            "{e}"
        );
    }

    #[test]
    fn model_specific_ranges_are_refused_with_the_parameter_named() {
        let mut c = SceneConfig {
            rheology: RheologyKind::PttLinear,
            ptt_epsilon: 0.6,
            ..Default::default()
        };
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("ptt_epsilon") && e.contains("0.6"), "{e}");
        c.rheology = RheologyKind::PttExponential;
        c.validate().unwrap();
        c.rheology = RheologyKind::Cross;
        c.cross_viscosity_inf = 5.0;
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.contains("cross_viscosity_inf") && e.contains("viscosity"),
            "{e}"
        );
    }

    #[test]
    fn huge_resolution_is_refused() {
        let c = SceneConfig {
            particles_per_diameter: 4000,
            ..Default::default()
        };
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.contains("particles_per_diameter") && e.contains("memory"),
            "{e}"
        );
    }

    #[test]
    fn string_twins_set_the_enumeration_by_name() {
        let mut c = SceneConfig::default();
        c.set("rheology_name", Value::Text("giesekus".into()))
            .unwrap();
        assert_eq!(c.rheology, RheologyKind::Giesekus);
        assert_eq!(c.item_name("rheology").unwrap(), "giesekus");
        let e = c
            .set("scheme_name", Value::Text("sph".into()))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scheme") && e.contains("'wcsph'"), "{e}");
        let e = c
            .set("rheology_name", Value::Integer(8))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("rheology_name") && e.contains("'giesekus'"),
            "{e}"
        );
        let twins: Vec<String> = name_variables().map(|(_, n, _)| n).collect();
        assert_eq!(
            twins,
            [
                "scene_name",
                "scheme_name",
                "rheology_name",
                "conformation_method_name",
                "artificial_stress_kind_name",
                "equation_of_state_name",
                "viscous_operator_name",
                "isph_frame_name",
                "isph_viscous_step_name",
                "isph_free_surface_name"
            ]
        );
        assert!(name_variable("plate_inclination_name").is_none());
    }

    #[test]
    fn value_references_are_unique() {
        let mut vrs: Vec<u32> = PARAMS
            .iter()
            .map(|p| p.value_reference)
            .chain(name_variables().map(|(_, _, vr)| vr))
            .chain(
                crate::diagnostics::OUTPUTS
                    .iter()
                    .map(|o| o.value_reference),
            )
            .collect();
        let n = vrs.len();
        vrs.sort();
        vrs.dedup();
        assert_eq!(
            vrs.len(),
            n,
            "every variable of every type has its own value reference"
        );
    }
}
