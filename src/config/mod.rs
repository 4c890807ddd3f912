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

mod macros;
mod spec;

pub use spec::{
    enumeration, integer, range_text, real, real_pos, Checked, ConfigError, Kind, ParamGroup,
    ParamSpec, ParamValue, Value,
};

use crate::rheology::{
    AnyRheology, Cross, FeneCr, FeneP, Giesekus, Newtonian, OldroydB, PttExponential, PttLinear,
};
pub use crate::rheology::{ConformationMethod, CONFORMATION_METHODS};

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

/// The parameter table: the rows of [`SceneConfig`], the single source of names, value
/// references, defaults and ranges.
pub const PARAMS: &[ParamSpec] = SceneConfig::ROWS;

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
    PARAMS
        .iter()
        .find(|p| p.name == name)
        .or_else(|| PARAMS.iter().find(|p| p.is_called(name)))
}

/// The parameter with a given FMU value reference.
pub fn param_by_vr(vr: u32) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|p| p.value_reference == vr)
}

/// The names of the rows of [`PARAMS`] that are FMU inputs ([`ParamSpec::input`]), in table
/// order. In the running simulation they live in [`crate::state::Inputs`].
pub fn input_names() -> impl Iterator<Item = &'static str> {
    PARAMS.iter().filter(|p| p.input).map(|p| p.name)
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

crate::params! {
    /// Everything that defines a simulation. Field names are the FMU parameter names.
    /// Defaults are Fang et al. 2006's Oldroyd-B drop (D = 2 cm, V = 1 m/s, nu = 0.004 m2/s,
    /// lambda1 = 0.02 s, lambda2 = 0.002 s, so beta = lambda2/lambda1 = 0.1), except the sound
    /// speed, which is automatic ([`SceneConfig::resolved_sound_speed`]: 12.60 m/s for this drop,
    /// Fang's 12.5 m/s within 1 %).
    pub struct SceneConfig {
        scene: Scene = enumeration::<Scene>("Scene", "drop"), vr 1, unit "";
            "Which flow to simulate",
        scheme: SchemeKind = enumeration::<SchemeKind>("Scheme", "wcsph"), vr 2, unit "";
            "SPH scheme",
        rheology: RheologyKind = enumeration::<RheologyKind>("Rheology", "oldroyd_b"), vr 3, unit "";
            "Constitutive model of the fluid",
        plate_inclination: f64 = Kind::Real { default: 0.0, min: 0.0, max: 90.0, min_open: false, max_open: true }, vr 4, unit "deg";
            "Angle of the plate to the horizontal; the plate runs downhill towards +x",
        impact_velocity: f64 = real(1.0, 0.0, 100.0), vr 5, unit "m/s";
            "Initial speed of the drop, vertically down",
        drop_diameter: f64 = real_pos(0.02, 10.0), vr 6, unit "m";
            "Diameter of the initial (circular) drop",
        initial_drop_height: f64 = real_pos(0.04, 100.0), vr 7, unit "m", alias "drop_height";
            "Height of the drop centre above the impact point at t = 0, measured vertically (scene files may also call it drop_height)",
        density: f64 = real_pos(1000.0, 1.0e5), vr 8, unit "kg/m3";
            "Reference density rho0",
        gravity: f64 = real(9.81, 0.0, 1000.0), vr 9, unit "m/s2";
            "Gravitational acceleration, vertically down",
        viscosity: f64 = real_pos(4.0, 1.0e6), vr 10, unit "Pa.s";
            "Total zero-shear viscosity eta0 (solvent + polymer)",
        viscosity_ratio: f64 = real(0.1, 0.0, 1.0), vr 11, unit "1";
            "Solvent to total viscosity beta = eta_s/eta0 (Fang's lambda2/lambda1)",
        relaxation_time: f64 = real_pos(0.02, 1.0e6), vr 12, unit "s";
            "Polymer relaxation time lambda (Fang's lambda1)",
        fene_L2: f64 = Kind::Real { default: 100.0, min: 2.0, max: 1.0e12, min_open: true, max_open: false }, vr 13, unit "1";
            "FENE extensibility L^2 (> 2 in 2D)",
        ptt_epsilon: f64 = real(0.25, 0.0, 10.0), vr 14, unit "1";
            "PTT extensibility parameter epsilon",
        giesekus_alpha: f64 = real(0.1, 0.0, 0.5), vr 15, unit "1";
            "Giesekus mobility alpha (0 <= alpha <= 0.5)",
        cross_viscosity_inf: f64 = real(0.4, 0.0, 1.0e6), vr 16, unit "Pa.s";
            "Cross model infinite-shear viscosity (Ren 2015 eq. 5)",
        cross_K: f64 = real(1.0, 0.0, 1.0e6), vr 17, unit "s";
            "Cross model time constant K (Ren 2015 eq. 5)",
        cross_m: f64 = real(1.0, 0.0, 10.0), vr 18, unit "1";
            "Cross model exponent m (Ren 2015 eq. 5)",
        particles_per_diameter: i64 = integer(20, 4, 4000), vr 19, unit "";
            "Resolution: lattice spacing dx = drop_diameter / particles_per_diameter",
        sound_speed: f64 = real(0.0, 0.0, 1.0e5), vr 20, unit "m/s";
            "Artificial speed of sound c in the equation of state; 0 = automatic: 10 times the largest speed the scene can reach (impact speed plus free fall), for about 1 % density variation. Ignored under isph (incompressible: no equation of state)",
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
        threads: i64 = integer(0, 0, 1024), vr 40, unit "";
            "Worker threads of this simulation's own thread pool; 0 = the RAYON_NUM_THREADS environment variable, else one per core. Results do not depend on it",
        channel_width: f64 = real_pos(0.02, 100.0), vr 41, unit "m";
            "Channel scene: distance H between the two walls; particles_per_diameter counts particles across it",
        channel_length: f64 = real(0.0, 0.0, 1000.0), vr 42, unit "m";
            "Channel scene: period along the flow (rounded to whole particle spacings); 0 = channel_width",
        body_force: f64 = real(80.0, 0.0, 1.0e6), vr 43, unit "m/s2";
            "Channel scene: body force per unit mass along the channel, switched on at t = 0 (gravity is off in the channel)",
        plate_velocity: f64 = real(0.0, -1000.0, 1000.0), vr 60, unit "m/s", input;
            "Input: velocity of the plate along its normal, positive away from the fluid; the plate moves rigidly and the walls follow. A co-simulation master may change it at every communication point; this is its start value",
        viscous_operator: ViscousOperator = enumeration::<ViscousOperator>("ViscousOperator", "auto"), vr 44, unit "";
            "Weakly compressible schemes: the solvent viscosity inside the stress (Fang's nested operator) or through Morris' Laplacian, which keeps shear layers at walls free of particle-scale zigzag",
        jet_width: f64 = real_pos(0.006, 10.0), vr 45, unit "m";
            "Jet scene: width D of the planar jet at the nozzle exit (King & Lind 2021: 6 mm); particles_per_diameter counts particles across it",
        nozzle_height: f64 = real_pos(0.072, 100.0), vr 46, unit "m";
            "Jet scene: height of the nozzle exit above the impact point, measured vertically (King & Lind 2021: 12 D)",
        jet_velocity: f64 = real(0.2, 0.0, 100.0), vr 47, unit "m/s", input;
            "Input: jet scene: speed of the fluid leaving the nozzle, vertically down (King & Lind 2021: 0.2 m/s). A co-simulation master (a pump or valve model) may change it at every communication point; this is its start value, which also sets the automatic sound speed",
        container_width: f64 = real(0.0, 0.0, 100.0), vr 48, unit "m";
            "Jet scene: distance between the container's side walls, centred on the impact point and perpendicular to the plate; 0 = no side walls",
        isph_frame: IsphFrame = enumeration::<IsphFrame>("IsphFrame", "lagrangian"), vr 49, unit "";
            "ISPH: Lagrangian particles with shifting, or Eulerian (fixed particles; only for domains without a free surface)",
        isph_viscous_step: ViscousStep = enumeration::<ViscousStep>("ViscousStep", "implicit"), vr 50, unit "";
            "ISPH: solvent viscosity implicit (the time step is then set by the flow speed and the polymer) or explicit as in King & Lind eq. (24)",
        isph_free_surface: IsphFreeSurface = enumeration::<IsphFreeSurface>("IsphFreeSurface", "auto"), vr 51, unit "";
            "ISPH: free-surface pressure; normal_stress = King & Lind eq. (35a)'s solvent normal stress with a pressure gradient consistent with it (the jet buckles), zero_pressure = p = 0 (the drop keeps its volume best); auto = normal_stress in the jet scene, zero_pressure elsewhere",
    }
}

/// Automatic sound speed over the largest expected flow speed: 10 for about 1 % density
/// variation (see [`SceneConfig::resolved_sound_speed`]).
pub const SOUND_SPEED_FACTOR: f64 = 10.0;

/// Largest number of particles (fluid + wall) a scene may ask for: about 2 GB of state.
pub const MAX_PARTICLES: f64 = 5.0e6;

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
        let checked = spec.kind.check(name, value)?;
        assert!(
            self.store(spec.name, checked),
            "every row has a field: {}",
            spec.name
        );
        Ok(())
    }

    /// Current value of a parameter by name (enumerations as their 1-based index).
    pub fn get(&self, name: &str) -> Result<Value, ConfigError> {
        let spec = param_spec(name).ok_or_else(|| ConfigError::Unknown(name.to_string()))?;
        Ok(self.value(spec.name).expect("every row has a field"))
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

    /// The start values of the inputs ([`input_names`]).
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
                (self.initial_drop_height - 0.5 * self.drop_diameter / theta.cos()).max(0.0)
            }
            Scene::Jet => {
                let u0 = self.jet_velocity;
                return (u0 * u0 + 2.0 * self.gravity * self.nozzle_height)
                    .sqrt()
                    .max(1e-3);
            }
            Scene::EllipticalDrop => self.initial_drop_height.max(0.0),
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
        assert_eq!(
            c.initial_drop_height, 0.05,
            "the older name still works alone"
        );
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
