//! Parameters: how each one is declared, checked and stored, and the groups shared by every
//! scene.
//!
//! A parameter is declared once, as a field of a group written with [`params!`](crate::params):
//! the field carries its row of the parameter table ([`ParamSpec`]: FMU name, which is also its
//! scene-file key, value reference, type, default, allowed range, unit and description), and the
//! macro generates the rest (the group's `Default`, reading and storing by name). Range checks
//! happen in one place ([`Kind::check`]): a value outside the row's range is refused with a
//! message naming the variable, the value and the range.
//!
//! The groups here belong to no scene: the fluid ([`FluidParams`]), the numerics ([`Numerics`])
//! and the plate ([`PlateParams`]). Each scene declares its own group in its file, and the
//! scene registry ([`crate::scene`]) assembles them with these into the configuration
//! (`SceneConfig`) and the full table, which generates `modelDescription/modelDescription.xml`
//! (checked by a test, so the FMU's interface and the solver cannot drift apart).

mod fluid;
mod macros;
mod numerics;
mod plate;
mod spec;

pub use fluid::{FluidParams, RheologyKind, RHEOLOGIES};
pub use numerics::{
    ArtificialStressKind, ConformationMethod, EquationOfState, IsphFrame, IsphFreeSurface,
    Numerics, ViscousOperator, ViscousStep, WallBoundary, ARTIFICIAL_STRESS_KINDS,
    CONFORMATION_METHODS, EQUATIONS_OF_STATE, ISPH_FRAMES, ISPH_FREE_SURFACES, SOUND_SPEED_FACTOR,
    VISCOUS_OPERATORS, VISCOUS_STEPS, WALL_BOUNDARIES,
};
pub use plate::{PlateCoupling, PlateParams, PLATE_COUPLINGS};
pub use spec::{
    enumeration, integer, range_text, real, real_pos, Checked, ConfigError, Kind, ParamGroup,
    ParamSpec, ParamValue, Value,
};

crate::params! {
    /// The group of a scene without parameters of its own.
    pub struct NoParams {}
}
