//! The configuration of a simulation ([`SceneConfig`], assembled by the registry): setting and
//! reading parameters by name, scene files, the checks that involve several parameters, and what
//! follows from it for the solver (spacing, sound speed, the scheme's constants). Everything a
//! scene decides is asked of the scene; nothing here names one.

use super::{param_spec, Scene, SceneConfig, SceneKind, PARAMS};
use crate::config::{range_text, ConfigError, Kind, ParamGroup, Value, SOUND_SPEED_FACTOR};
use crate::diagnostics::SharedOutputs;
use crate::eos::Eos;
use crate::scheme::params::Params;
use crate::state::State;
use serde::{Deserialize, Serialize};

/// Largest number of particles (fluid + wall) a scene may ask for: about 2 GB of state.
pub const MAX_PARTICLES: f64 = 5.0e6;

/// The values of the FMU inputs (the rows marked input, [`super::input_rows`]), by name: what a
/// co-simulation master may change between communication points. They are held constant over a
/// communication step (FMI 2.0 co-simulation without input derivatives).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Inputs(Vec<(String, f64)>);

impl Inputs {
    /// The value of the input called `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.iter().find(|(n, _)| n == name).map(|p| p.1)
    }

    /// These inputs with `name` set to `value` (checked when they are put in force).
    pub fn with(mut self, name: &str, value: f64) -> Self {
        match self.0.iter_mut().find(|(n, _)| n == name) {
            Some(p) => p.1 = value,
            None => self.0.push((name.to_string(), value)),
        }
        self
    }

    /// (name, value) of every input.
    pub fn iter(&self) -> impl Iterator<Item = (&str, f64)> {
        self.0.iter().map(|(n, v)| (n.as_str(), *v))
    }
}

impl SceneConfig {
    /// The behaviour of the configured scene.
    pub fn scene_def(&self) -> &'static dyn Scene {
        self.scene.scene()
    }

    /// Set one parameter by its FMU name (or its older alias), checking type and range against
    /// its row. Enumerations accept their name (`Value::Text`) or their 1-based index
    /// (`Value::Integer`). A String twin (`rheology_name`, see [`super::name_variables`]) takes
    /// an item name.
    pub fn set(&mut self, name: &str, value: Value) -> Result<(), ConfigError> {
        if param_spec(name).is_none() {
            if let Some(p) = super::name_variable(name) {
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

    /// The values of the inputs.
    pub fn inputs(&self) -> Inputs {
        Inputs(
            super::input_rows()
                .map(|p| match self.value(p.name) {
                    Some(Value::Real(x)) => (p.name.to_string(), x),
                    other => unreachable!("input {} is a real, not {other:?}", p.name),
                })
                .collect(),
        )
    }

    /// Put `inputs` in this configuration, each checked against its row; an input not named
    /// keeps its value. Refused (and nothing changed) if one is not an input or out of range.
    pub fn apply_inputs(&mut self, inputs: &Inputs) -> Result<(), ConfigError> {
        let mut next = self.clone();
        for (name, x) in inputs.iter() {
            match param_spec(name) {
                Some(p) if p.input => {
                    if !x.is_finite() {
                        return Err(ConfigError::Inconsistent(format!(
                            "{name} = {x} is not a finite number"
                        )));
                    }
                    next.set(p.name, Value::Real(x))?
                }
                Some(_) => {
                    return Err(ConfigError::Inconsistent(format!(
                        "'{name}' is a parameter, not an input"
                    )))
                }
                None => return Err(ConfigError::Unknown(name.to_string())),
            }
        }
        *self = next;
        Ok(())
    }

    /// Particle spacing dx = L / particles_per_diameter, L the scene's reference length (Fang
    /// 2006 section 4: a Cartesian lattice).
    pub fn dx(&self) -> f64 {
        self.scene_def().reference_length(self) / self.numerics.particles_per_diameter as f64
    }

    /// Smoothing length h = smoothing_ratio * dx (Fang uses h = 1.5 dx).
    pub fn h(&self) -> f64 {
        self.numerics.smoothing_ratio * self.dx()
    }

    /// Largest speed the scene's fluid can reach from its initial conditions \[m/s\] (see
    /// [`Scene::max_expected_speed`]): the reference of the automatic sound speed.
    pub fn max_expected_speed(&self) -> f64 {
        self.scene_def().max_expected_speed(self)
    }

    /// The sound speed the run uses \[m/s\]: `sound_speed` when it is set (> 0), otherwise
    /// [`SOUND_SPEED_FACTOR`] times [`SceneConfig::max_expected_speed`]. A weakly compressible
    /// scheme's density varies by about (U/c)^2 (Monaghan 1994; Morris, Fox & Zhu 1997), so
    /// c = 10 U keeps it near 1 %. For Fang 2006's default drop (V = 1 m/s,
    /// 3 cm of free fall) that gives c = 12.60 m/s against Fang's 12.5 m/s.
    pub fn resolved_sound_speed(&self) -> f64 {
        if self.numerics.sound_speed > 0.0 {
            self.numerics.sound_speed
        } else {
            SOUND_SPEED_FACTOR * self.max_expected_speed()
        }
    }

    /// The equation of state of the weakly compressible schemes.
    pub fn eos(&self) -> Eos {
        Eos::new(
            self.numerics.equation_of_state,
            self.fluid.density,
            self.resolved_sound_speed(),
        )
    }

    /// The configuration the solver runs (see [`Scene::effective_config`]).
    pub fn effective(&self) -> SceneConfig {
        self.scene_def().effective_config(self)
    }

    /// The scheme's constants for this (effective) configuration: the fluid's and the
    /// numerics', and what the scene says about its domain (body force, periodicity, size, free
    /// surface, which viscous operator `auto` means).
    pub fn scheme_params(&self) -> Params {
        self.scheme_params_in::<2>()
    }

    /// [`SceneConfig::scheme_params`] in N dimensions: the scene's body force (x, y) acts
    /// along (x, z) in 3D, the plane of the 2D flow.
    pub fn scheme_params_in<const N: usize>(&self) -> Params<N> {
        use crate::config::ViscousOperator;
        let scene = self.scene_def();
        let mut p = Params::<N>::in_dimension(
            &self.fluid,
            &self.numerics,
            self.dx(),
            self.resolved_sound_speed(),
        );
        p.domain_radius = scene.domain_radius(self);
        p.domain = scene.domain(self);
        let body = scene.body_force(self);
        p.gravity = crate::dim::Vector::<N>::zeros();
        p.gravity[0] = body.x;
        p.gravity[N - 1] = body.y;
        p.viscous_laplacian = match self.numerics.viscous_operator {
            ViscousOperator::Auto => scene.viscous_laplacian(),
            op => op == ViscousOperator::Laplacian,
        };
        p.free_surface = scene.has_free_surface();
        p.background_pressure = scene.background_pressure(self);
        p.auto_free_surface = scene.auto_free_surface();
        p
    }

    /// The shared outputs of a state of this (effective) configuration (see
    /// [`SharedOutputs::compute_for`]).
    /// The outputs of a 2D state: the scene's ([`Scene::outputs`]) with the `_total` ones
    /// counted over [`SceneConfig::depth`].
    pub fn outputs_2d(&self, st: &State) -> super::Outputs {
        let mut o = self.scene_def().outputs(st, self);
        o.shared.complete_2d(self.depth());
        o
    }

    pub fn shared_outputs(&self, st: &State) -> SharedOutputs {
        SharedOutputs::compute_for(
            st,
            self.dx(),
            self.fluid.density,
            self.scheme.is_incompressible(),
        )
    }

    /// The scene's warning for this configuration, if any (see [`Scene::warning`]).
    pub fn warning(&self) -> Option<&'static str> {
        self.scene_def().warning(self)
    }

    /// Checks that involve several parameters. Single-value ranges were already enforced by
    /// [`SceneConfig::set`]; they are checked again here so a config built field by field in
    /// Rust is held to the same table.
    ///
    /// The checks that belong to one scene (a drop that starts inside its plate) are the
    /// scene's own: `Simulation::validate` runs both.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for p in PARAMS.iter() {
            let v = self.get(p.name)?;
            self.clone().set(p.name, v)?;
        }
        let scene = self.scene_def();
        self.scheme.validate(
            &self.numerics,
            scene.has_free_surface(),
            self.scene.as_str(),
            &super::closed_scenes(),
        )?;
        self.fluid.validate()?;
        self.validate_dimension()?;
        let estimate = scene.estimated_particles(self);
        if estimate > MAX_PARTICLES {
            return Err(ConfigError::Inconsistent(format!(
                "particles_per_diameter = {} would need about {:.2e} particles, more than the {:.0e} that fit in memory",
                self.numerics.particles_per_diameter, estimate, MAX_PARTICLES
            )));
        }
        Ok(())
    }

    /// Under `dimension = 3`: a scene with a 3D form ([`Scene::three_dimensional`]) and a wall
    /// model built for a plane (dummy particles for the weakly compressible schemes, `auto`
    /// meaning them in 3D; mirrors for ISPH). Each refusal names the parameter and says why.
    fn validate_dimension(&self) -> Result<(), ConfigError> {
        use crate::config::WallBoundary;
        if self.numerics.dimension != 3 {
            return Ok(());
        }
        let refuse = |why: String| Err(ConfigError::Inconsistent(format!("dimension = 3: {why}")));
        if !self.scene_def().three_dimensional() {
            return refuse(format!(
                "the scene '{}' has no 3D form yet (scenes with one: {})",
                self.scene,
                super::three_dimensional_scenes()
            ));
        }
        match self.numerics.wall_boundary {
            WallBoundary::Image | WallBoundary::Ghost => refuse(format!(
                "wall_boundary = {}: Fang's image and Ren's ghost particles are built as one row of \
                 columns along a 2D wall line; in 3D the weakly compressible schemes take dummy \
                 particles (wall_boundary = dummy or auto), three layers under the plane",
                self.numerics.wall_boundary
            )),
            _ => Ok(()),
        }
    }

    /// The wall model `wall_boundary` means for `wall` under this configuration's scheme
    /// ([`crate::boundary::resolve`]; a choice the scheme refuses, which building the scheme
    /// reports, reads as the scheme's own model here).
    pub fn wall_model<const N: usize>(
        &self,
        wall: &crate::boundary::wall::Wall<N>,
    ) -> crate::boundary::Model {
        let paper = self.scheme.paper_wall_model();
        crate::boundary::resolve(self.numerics.wall_boundary, paper, wall).unwrap_or(paper)
    }

    /// The length across the plane of a 2D flow that the `_total` outputs count \[m\]:
    /// `depth`, or the scene's reference length (the drop's diameter) when it is 0.
    pub fn depth(&self) -> f64 {
        if self.plate.depth > 0.0 {
            self.plate.depth
        } else {
            self.scene_def().reference_length(self)
        }
    }

    /// The defaults of a scene: the table's ([`PARAMS`], Fang's drop) with the scene's own
    /// values over them ([`Scene::defaults`]; the jet: King & Lind's case). The table stays the
    /// one source of names, ranges and units, and of the FMU's start values (one per variable,
    /// so an FMU that is told only `scene = jet` runs the table's values); scene files start
    /// from these.
    pub fn for_scene(scene: SceneKind) -> Self {
        let mut c = SceneConfig {
            scene,
            ..Default::default()
        };
        let table: toml::Table = scene
            .scene()
            .defaults()
            .parse()
            .expect("a scene's defaults are TOML");
        c.apply_table(table)
            .expect("a scene's defaults are within the table's ranges");
        c
    }

    /// Read a flat TOML scene file whose keys are the FMU parameter names. Missing keys keep
    /// their defaults, those of the scene it names ([`SceneConfig::for_scene`]); an unknown key
    /// or a bad value is an error naming it, and so is a file that gives both a parameter's name
    /// and its older name (`initial_drop_height` and `drop_height`).
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| ConfigError::Parse(e.to_string()))?;
        for p in PARAMS.iter() {
            if let Some(alias) = p.alias {
                if table.contains_key(alias) && table.contains_key(p.name) {
                    return Err(ConfigError::Inconsistent(format!(
                        "both '{}' ({}) and its older name '{alias}' ({}) are given: keep one",
                        p.name, table[p.name], table[alias]
                    )));
                }
            }
        }
        let mut cfg = SceneConfig::default();
        if let Some(scene) = table.get("scene").and_then(|v| v.as_str()) {
            // A scene that is not one is reported by `set` below.
            if let Some(scene) = SceneKind::parse(scene) {
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
        for p in PARAMS.iter() {
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

impl crate::rheology::AnyRheology {
    /// The model of a configuration's fluid ([`AnyRheology::from_fluid`](crate::rheology::AnyRheology::from_fluid)).
    pub fn from_config(cfg: &SceneConfig) -> Result<Self, ConfigError> {
        Ok(Self::from_fluid(&cfg.fluid))
    }
}

#[cfg(test)]
#[path = "configuration_tests.rs"]
mod tests;
