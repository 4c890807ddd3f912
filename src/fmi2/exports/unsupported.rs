//! The entry points of `fmi2Functions.h` this FMU has but does not support (Model Exchange,
//! directional and input/output derivatives, cancelling a step): each answers `fmi2Error` with
//! the reason.

#![allow(non_snake_case)]

use super::*;

/// An entry point the FMU has but does not support: it reports why through the logger and
/// returns fmi2Error (through [`guarded`], so it too never panics across the boundary). With
/// `-> T` after the argument list the status is returned as `T` (FMI 3.0's `fmi3Status`, same
/// values).
macro_rules! unsupported {
    ($name:ident($($arg:ident: $ty:ty),* $(,)?), $why:expr $(,)?) => {
        unsupported!($name($($arg: $ty),*) -> $crate::fmi2::types::fmi2Status, $why);
    };
    ($name:ident($($arg:ident: $ty:ty),* $(,)?) -> $status:ty, $why:expr $(,)?) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: *mut std::os::raw::c_void, $($arg: $ty),*) -> $status {
            $crate::fmi2::exports::guarded(c, stringify!($name), |i| {
                i.unsupported(stringify!($name), $why)
            }) as $status
        }
    };
}
/// For the FMI 3.0 entry points this FMU does not provide (`crate::fmi3`).
pub(crate) use unsupported;

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.9: partial derivatives (not provided)
// ---------------------------------------------------------------------------------------------

unsupported!(
    fmi2GetDirectionalDerivative(
        _vUnknown_ref: *const fmi2ValueReference,
        _nUnknown: usize,
        _vKnown_ref: *const fmi2ValueReference,
        _nKnown: usize,
        _dvKnown: *const fmi2Real,
        _dvUnknown: *mut fmi2Real,
    ),
    "directional derivatives are not provided (providesDirectionalDerivative = false)"
);

// ---------------------------------------------------------------------------------------------
// FMI 2.0 chapter 3: Model Exchange (not supported)
// ---------------------------------------------------------------------------------------------

const NO_ME: &str = "Model Exchange is not supported: ViscoSPH is a Co-Simulation FMU";

unsupported!(fmi2EnterEventMode(), NO_ME);

unsupported!(fmi2NewDiscreteStates(_fmi2eventInfo: *mut fmi2EventInfo), NO_ME);

unsupported!(fmi2EnterContinuousTimeMode(), NO_ME);

unsupported!(
    fmi2CompletedIntegratorStep(
        _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
        _enterEventMode: *mut fmi2Boolean,
        _terminateSimulation: *mut fmi2Boolean,
    ),
    NO_ME
);

unsupported!(fmi2SetTime(_time: fmi2Real), NO_ME);

unsupported!(fmi2SetContinuousStates(_x: *const fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetDerivatives(_derivatives: *mut fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetEventIndicators(_eventIndicators: *mut fmi2Real, _ni: usize), NO_ME);

unsupported!(fmi2GetContinuousStates(_x: *mut fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetNominalsOfContinuousStates(_x_nominal: *mut fmi2Real, _nx: usize), NO_ME);

// ---------------------------------------------------------------------------------------------
// FMI 2.0 chapter 4: Co-Simulation
// ---------------------------------------------------------------------------------------------

unsupported!(
    fmi2SetRealInputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *const fmi2Real,
    ),
    "the inputs are held constant over a communication step; their derivatives are not used (canInterpolateInputs = false)"
);

unsupported!(
    fmi2GetRealOutputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *mut fmi2Real,
    ),
    "output derivatives are not provided (maxOutputDerivativeOrder = 0)"
);

unsupported!(
    fmi2CancelStep(),
    "no step is in progress: fmi2DoStep is synchronous (canRunAsynchronuously = false)"
);
