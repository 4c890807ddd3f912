//! Scenes: the initial state of a flow, its walls, what happens at every step (inflow, for the
//! jet), what is measured in it and how a run of it is reported. A scene is one file: a type that
//! implements [`Scene`] (behaviour) and [`SceneType`] (its name, its parameter group declared
//! with [`params!`](crate::params), its output group declared with
//! [`outputs!`](crate::outputs)). The registry below is the one place that lists the scenes:
//! from it come the `scene` parameter and its items, the configuration [`SceneConfig`] (the
//! shared groups and every scene's), the outputs [`Outputs`] (the shared ones and every
//! scene's), and the one `match` that maps the `scene` parameter to its behaviour. A new scene is
//! a new file and one line in the `scenes!` list below.
//!
//! Nothing outside this file and `scheme/mod.rs` tests which scene or scheme runs: what differs
//! between scenes is a method of [`Scene`] (with a default that most scenes keep), and what
//! differs between schemes is data [`SchemeKind`] provides.

pub mod averages;
mod configuration;
pub mod report;
mod table;

pub use averages::{FieldAverage, Sample, SteadyWindow};
pub use configuration::{Inputs, MAX_PARTICLES};
pub use report::{time_text, NoPredictions, Prediction, Predictions, TimePlot, TimePlotPanel};
pub use table::{
    input_rows, name_variable, name_variable_by_vr, name_variables, output_index, param_by_vr,
    param_spec, NAME_SUFFIX, NAME_VR_OFFSET, OUTPUTS, OUTPUT_ARRAYS, PARAMS,
};

use crate::boundary::wall::Wall;
use crate::choice::Choice;
use crate::config::{
    ConfigError, FluidParams, IsphFreeSurface, Numerics, ParamGroup, ParamSpec, ParamValue,
    PlateParams, Value,
};
use crate::diagnostics::{OutputArray, OutputGroup, OutputSpec, SharedOutputs};
use crate::dim::Tensor;
use crate::neighbors::Domain;
use crate::particles::Fluid;
pub use crate::scheme::SchemeKind;
use crate::state::State;
use crate::{Mat2, Vec2};
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// One kind of flow: how it is built, driven and measured, and how a run of it is reported.
/// Every method but [`Scene::effective_config`] gets the configuration the solver runs
/// (`SceneConfig::effective`; the scales and [`Scene::reference_length`] read only what it does
/// not change), in which the scene's own group is `cfg.<scene>` (e.g. `cfg.jet`).
pub trait Scene: Send + Sync {
    // ---- Parameters and scales.

    /// What a scene file that names this scene gets for the keys it leaves out, over the
    /// table's defaults: a flat TOML text read through the table, so every value is checked
    /// against its row's range. Empty: the table's own.
    fn defaults(&self) -> &'static str {
        ""
    }

    /// The length `particles_per_diameter` counts particles across \[m\]: the lattice spacing is
    /// dx = reference_length / particles_per_diameter.
    fn reference_length(&self, cfg: &SceneConfig) -> f64;

    /// Largest speed the scene's fluid can reach from its initial conditions [m/s], the
    /// reference of the automatic sound speed (`SceneConfig::resolved_sound_speed`). At least
    /// 1 mm/s, so a scene with nothing moving still gets a finite time step.
    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64;

    /// Velocity scale U \[m/s\], for dimensionless measures such as the pressure roughness
    /// (normalised by rho0 U^2).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64;

    /// Time scale \[s\] for dimensionless plots (t* = t / time scale).
    fn time_scale(&self, cfg: &SceneConfig) -> f64;

    /// Rough particle count (fluid + wall), for the memory check.
    fn estimated_particles(&self, cfg: &SceneConfig) -> f64 {
        let ppd = cfg.numerics.particles_per_diameter as f64;
        std::f64::consts::FRAC_PI_4 * ppd * ppd
    }

    /// Checks of the configuration that belong to this scene (beyond the parameter table's).
    fn validate(&self, _cfg: &SceneConfig) -> Result<(), ConfigError> {
        Ok(())
    }

    /// The configuration the solver runs: the scene's own physics over the shared groups of
    /// the user's (a scene that fixes its fluid, switches gravity off...).
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        cfg.clone()
    }

    // ---- What the scheme is told about the domain.

    /// Whether the fluid has a free surface (every scene but a closed one).
    fn has_free_surface(&self) -> bool {
        true
    }

    /// What `isph_free_surface = auto` means here (module documentation of `scheme::isph`).
    fn auto_free_surface(&self) -> IsphFreeSurface {
        IsphFreeSurface::ZeroPressure
    }

    /// Background pressure of the weakly compressible schemes \[Pa\], added to the equation of
    /// state's pressure: a closed domain's pressure is fixed only up to a constant, and a
    /// constant that keeps the pressure positive keeps the fluid out of tension, where SPH's
    /// particles clump (the tensile instability) and walls pull them in. 0 (the default) for
    /// a free surface, whose pressure is zero.
    fn background_pressure(&self, _cfg: &SceneConfig) -> f64 {
        0.0
    }

    /// Whether the `auto` viscous operator means Morris' Laplacian (see
    /// [`crate::operators::stress`]) rather than Fang's nested form.
    fn viscous_laplacian(&self) -> bool {
        false
    }

    /// The domain the pairs see (open unless the scene is periodic).
    fn domain(&self, _cfg: &SceneConfig) -> Domain {
        Domain::OPEN
    }

    /// Whether the scene's own inputs in `now` lie within the range a run set up with `setup`
    /// (the configuration it was built from: start values and limits, which resolved the sound
    /// speed) can take; the message names the input, its value and the parameter to raise.
    /// The plate's inputs are checked for every scene (`Simulation::set_inputs`).
    fn check_input_range(&self, _setup: &SceneConfig, _now: &SceneConfig) -> Result<(), String> {
        Ok(())
    }

    /// Largest distance from the origin a particle may reach before the run stops \[m\].
    fn domain_radius(&self, cfg: &SceneConfig) -> f64;

    /// Body force per unit mass [m/s2]: gravity, vertically down, unless the scene drives the
    /// flow otherwise.
    fn body_force(&self, cfg: &SceneConfig) -> Vec2 {
        Vec2::new(0.0, -cfg.fluid.gravity)
    }

    /// Whether the input `plate_velocity` may move this scene's plate ([`Scene::plate_wall`]),
    /// whose motion is then [`Motion::Input`](crate::boundary::plate::Motion::Input). Only a
    /// scene with one free-standing plate can: a channel wall moved along its normal would
    /// squeeze the channel, and the elliptical drop has no wall.
    fn has_moving_plate(&self) -> bool {
        false
    }

    /// Which of [`Scene::build`]'s walls is "the plate" the shared outputs refer to (the frame
    /// of the drop's width and height, `plate_displacement`, the normal and tangential wall
    /// force) and the input `plate_velocity` moves when [`Scene::has_moving_plate`]; None: the
    /// outputs are in the global frame.
    fn plate_wall(&self) -> Option<usize> {
        None
    }

    // ---- The state.

    /// The initial fluid and walls. `rest` is the model's conformation at rest, or None for
    /// models without a conformation tensor.
    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Wall>);

    /// The initial state: [`Scene::build`]'s fluid and walls, and whatever else the scene
    /// keeps in the state (the jet's inlet and its bookkeeping).
    fn initial_state(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> State {
        let (fluid, walls) = self.build(cfg, rest);
        State::new(fluid, walls, self.plate_wall())
    }

    /// Called before every step (inflow, the cylinder array's steady-state criterion).
    fn before_step(&self, _cfg: &SceneConfig, _st: &mut State) {}

    /// Once the flow of a state is steady: the span of time over which a run averages its
    /// fields ([`averages::FieldAverage`]) and whether the run ends with it. None for a scene
    /// without a steady state, and before it.
    fn steady_window(&self, _cfg: &SceneConfig, _st: &State) -> Option<SteadyWindow> {
        None
    }

    // ---- Three dimensions (`dimension = 3`).

    /// Whether the scene has a three-dimensional form: [`Scene::initial_state_3d`] builds it
    /// and [`Scene::outputs_3d`] measures it. A scene without one is refused under
    /// `dimension = 3`, by name.
    fn three_dimensional(&self) -> bool {
        false
    }

    /// The initial state in three dimensions (the 2D plane of the flow is x-z, gravity along
    /// -z, y across it), or None for a scene without a 3D form. `rest` as in
    /// [`Scene::build`].
    fn initial_state_3d(&self, _cfg: &SceneConfig, _rest: Option<Tensor<3>>) -> Option<State<3>> {
        None
    }

    /// [`Scene::before_step`] for a 3D state (the round jet's inflow).
    fn before_step_3d(&self, _cfg: &SceneConfig, _st: &mut State<3>) {}

    /// The outputs of a 3D state: the shared ones (per-depth outputs 0, the `_total` ones in
    /// newtons and joules, `drop_width_transverse` across the plate); the scene's own groups
    /// hold 0 unless the scene measures them in 3D. Under the incompressible scheme, with a free
    /// surface,
    /// `volume_error` is the covered volume's ([`crate::diagnostics::covered_volume`]) over
    /// N dx^3, as the covered area in 2D.
    fn outputs_3d(&self, st: &State<3>, cfg: &SceneConfig) -> Outputs {
        let mut shared = SharedOutputs::compute(st, cfg.dx(), cfg.fluid.density);
        if cfg.scheme.is_incompressible() && self.has_free_surface() && !st.fluid.is_empty() {
            let dx = cfg.dx();
            shared.volume_error = crate::diagnostics::covered_volume(&st.fluid.x, dx)
                / (st.fluid.len() as f64 * dx * dx * dx)
                - 1.0;
        }
        Outputs {
            shared,
            ..Default::default()
        }
    }

    /// The outputs of a state: the shared ones ([`SceneConfig::shared_outputs`]) and the
    /// scene's own; every other scene's hold 0.
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        Outputs {
            shared: cfg.shared_outputs(st),
            ..Default::default()
        }
    }

    // ---- Reports (the CLI's `viscosph run`, the FMU's log).

    /// A warning for a configuration that runs but not as the user likely expects, told once
    /// (the CLI on stderr, the FMU under `logStatusWarning`).
    fn warning(&self, _cfg: &SceneConfig) -> Option<&'static str> {
        None
    }

    /// Lines that sum up a run: the state at its end and its record of outputs. `predictions`
    /// are models outside the solver the scene may quote (see [`Predictions`]).
    fn summary(
        &self,
        _cfg: &SceneConfig,
        _st: &State,
        _series: &[(f64, Outputs)],
        _predictions: &dyn Predictions,
    ) -> Vec<String> {
        Vec::new()
    }

    /// [`Scene::summary`] of a 3D run: the state at its end and its record of outputs.
    fn summary_3d(
        &self,
        _cfg: &SceneConfig,
        _st: &State<3>,
        _series: &[(f64, Outputs)],
        _predictions: &dyn Predictions,
    ) -> Vec<String> {
        Vec::new()
    }

    /// What a plot of the run's outputs against time shows (`width_height.png`): by default
    /// W* = width / D and H* = height / D against t* = t / time scale, D the reference length.
    fn time_plot(&self, cfg: &SceneConfig) -> TimePlot {
        report::extent_plot(cfg, self.reference_length(cfg), self.time_scale(cfg))
    }

    /// The caption of a snapshot at time `t`: t* and t by default.
    fn time_label(&self, cfg: &SceneConfig, t: f64) -> String {
        format!(
            "t* = {:.2} (t = {})",
            t / self.time_scale(cfg),
            time_text(t)
        )
    }

    /// The title of a sheet of particle snapshots coloured by `field`.
    fn snapshot_title(&self, cfg: &SceneConfig, field: &str) -> String;

    /// Columns of a sheet of `panels` particle snapshots.
    fn snapshot_columns(&self, _panels: usize) -> usize {
        3
    }

    /// An inlet to draw on the snapshots: its opening from x0 to x1 at height y \[m\].
    fn inlet_mark(&self, _cfg: &SceneConfig) -> Option<(f64, f64, f64)> {
        None
    }

    /// For a scene whose sound speed, when `sound_speed` is 0 (automatic), is its own rather
    /// than ten times its largest expected speed: where it comes from, e.g. "the elliptical
    /// drop's own".
    fn own_sound_speed(&self) -> Option<&'static str> {
        None
    }

    /// For a scene that takes only some parameters from the configuration (its own physics
    /// fixes the rest): a note and the parameters a record of the run lists.
    fn taken_parameters(&self) -> Option<(&'static str, &'static [&'static str])> {
        None
    }
}

/// What the registry needs to know of a scene at compile time.
pub trait SceneType: Scene + 'static {
    /// The item of the `scene` parameter (FMU Enumeration item, scene-file value).
    const NAME: &'static str;
    /// The item's description.
    const DESCRIPTION: &'static str;
    /// The scene's own parameters ([`crate::config::NoParams`] for none).
    type Params: ParamGroup
        + Default
        + Clone
        + PartialEq
        + std::fmt::Debug
        + Serialize
        + DeserializeOwned;
    /// The scene's own outputs ([`crate::diagnostics::NoOutputs`] for none).
    type Outputs: OutputGroup
        + Default
        + Copy
        + PartialEq
        + std::fmt::Debug
        + Serialize
        + DeserializeOwned;
}

/// The registry: from the list of scenes, the `scene` parameter ([`SceneKind`], its items and
/// its row), the configuration ([`SceneConfig`]) and the outputs ([`Outputs`]).
macro_rules! scenes {
    ($($variant:ident => $module:ident :: $scene:ident),+ $(,)?) => {
        $(pub mod $module;)+

        /// The flow to simulate: the `scene` parameter. Item order is the FMU's (append only).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum SceneKind {
            $($variant),+
        }

        /// The items of the `scene` parameter: (name, description), in FMU order.
        pub const SCENES: &[(&str, &str)] = &[
            $((<$module::$scene as SceneType>::NAME, <$module::$scene as SceneType>::DESCRIPTION)),+
        ];

        impl SceneKind {
            /// The scene's behaviour.
            pub fn scene(self) -> &'static dyn Scene {
                match self {
                    $(SceneKind::$variant => &$module::$scene),+
                }
            }
        }

        impl Choice for SceneKind {
            const ITEMS: &'static [(&'static str, &'static str)] = SCENES;
            fn name(self) -> &'static str {
                match self {
                    $(SceneKind::$variant => <$module::$scene as SceneType>::NAME),+
                }
            }
            fn from_name(s: &str) -> Option<Self> {
                [$(SceneKind::$variant),+].into_iter().find(|k| k.name() == s)
            }
        }

        /// Everything that defines a simulation: which scene under which scheme, the shared
        /// groups, and every scene's own group (only the running scene's is read). Field names
        /// of the groups are the FMU parameter names.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        pub struct SceneConfig {
            pub scene: SceneKind,
            pub scheme: SchemeKind,
            pub fluid: FluidParams,
            pub numerics: Numerics,
            pub plate: PlateParams,
            $(pub $module: <$module::$scene as SceneType>::Params,)+
        }

        impl Default for SceneConfig {
            /// The table's defaults: Fang et al. 2006's Oldroyd-B drop.
            fn default() -> Self {
                Self {
                    scene: ParamValue::from_checked(SCENE_ROW.kind.default_value()),
                    scheme: ParamValue::from_checked(crate::scheme::SCHEME_ROW.kind.default_value()),
                    fluid: Default::default(),
                    numerics: Default::default(),
                    plate: Default::default(),
                    $($module: Default::default(),)+
                }
            }
        }

        impl ParamGroup for SceneConfig {
            fn collect_rows(out: &mut Vec<&'static ParamSpec>) {
                out.push(&SCENE_ROW);
                out.push(&crate::scheme::SCHEME_ROW);
                FluidParams::collect_rows(out);
                Numerics::collect_rows(out);
                PlateParams::collect_rows(out);
                $(<$module::$scene as SceneType>::Params::collect_rows(out);)+
            }
            fn value(&self, name: &str) -> Option<Value> {
                match name {
                    "scene" => Some(self.scene.to_value()),
                    "scheme" => Some(self.scheme.to_value()),
                    _ => self
                        .fluid
                        .value(name)
                        .or_else(|| self.numerics.value(name))
                        .or_else(|| self.plate.value(name))
                        $(.or_else(|| self.$module.value(name)))+,
                }
            }
            fn store(&mut self, name: &str, v: crate::config::Checked) -> bool {
                match name {
                    "scene" => self.scene = SceneKind::from_checked(v),
                    "scheme" => self.scheme = SchemeKind::from_checked(v),
                    _ => {
                        return self.fluid.store(name, v)
                            || self.numerics.store(name, v)
                            || self.plate.store(name, v)
                            $(|| self.$module.store(name, v))+
                    }
                }
                true
            }
        }

        /// Values of every output at one time: the shared ones and every scene's own group
        /// (those of the scenes not running hold 0).
        #[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
        pub struct Outputs {
            pub shared: SharedOutputs,
            $(pub $module: <$module::$scene as SceneType>::Outputs,)+
        }

        impl Outputs {
            /// The output rows in group order (the shared group first, then the scenes').
            fn collect_rows(out: &mut Vec<&'static OutputSpec>) {
                out.extend(SharedOutputs::rows());
                $(out.extend(<$module::$scene as SceneType>::Outputs::rows());)+
            }
            /// The array rows in group order.
            fn collect_arrays(out: &mut Vec<&'static OutputArray>) {
                out.extend(SharedOutputs::ARRAYS);
                $(out.extend(<$module::$scene as SceneType>::Outputs::ARRAYS);)+
            }
            /// The values in group order.
            fn group_values(&self) -> Vec<f64> {
                let mut v = Vec::new();
                self.shared.push_values(&mut v);
                $(self.$module.push_values(&mut v);)+
                v
            }
            /// Set the values from `v`, in group order.
            fn set_group_values(&mut self, v: &[f64]) {
                let rest = self.shared.take_values(v);
                $(let rest = self.$module.take_values(rest);)+
                debug_assert!(rest.is_empty());
            }
        }
    };
}

scenes! {
    Drop => drop::Drop,
    Jet => jet::Jet,
    Channel => channel::Channel,
    EllipticalDrop => elliptical_drop::EllipticalDrop,
    CylinderArray => cylinder_array::CylinderArray,
}

/// The row of the `scene` parameter.
pub const SCENE_ROW: ParamSpec =
    ParamSpec::choice::<SceneKind>("scene", 1, "Scene", "drop", "Which flow to simulate");

impl SceneKind {
    /// The snake_case name used in the FMU and in scene files.
    pub fn as_str(self) -> &'static str {
        self.name()
    }
    /// Parse the snake_case name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::from_name(s)
    }
}

impl std::fmt::Display for SceneKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The names of the scenes for which `test` holds, in registry order.
fn names_where(test: impl Fn(&dyn Scene) -> bool) -> Vec<&'static str> {
    SCENES
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| SceneKind::from_name(n).is_some_and(|k| test(k.scene())))
        .collect()
}

/// The scenes without a free surface, quoted, for messages ("'channel'").
pub fn closed_scenes() -> String {
    let names: Vec<String> = names_where(|s| !s.has_free_surface())
        .iter()
        .map(|n| format!("'{n}'"))
        .collect();
    names.join(" or ")
}

/// The scenes with a 3D form, quoted, for messages ("'drop'").
pub fn three_dimensional_scenes() -> String {
    let names: Vec<String> = names_where(|s| s.three_dimensional())
        .iter()
        .map(|n| format!("'{n}'"))
        .collect();
    names.join(", ")
}

/// The scenes whose plate the input `plate_velocity` moves, for messages ("the drop").
pub fn moving_plate_scenes() -> String {
    let names: Vec<String> = names_where(|s| s.has_moving_plate())
        .iter()
        .map(|n| format!("the {n}"))
        .collect();
    names.join(" or ")
}
