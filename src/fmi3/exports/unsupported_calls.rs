//! The fmi3 functions of the standard that this Co-Simulation FMU exports but does not provide
//! (Model Exchange, Event Mode, clocks): fmpy resolves every one of them when it loads a
//! binary, so each is there and answers fmi3Error with the reason logged.

use super::*;

const NO_EVENT_MODE: &str = "ViscoSPH has no Event Mode (hasEventMode = false)";
const NO_ME: &str = "Model Exchange is not supported: ViscoSPH is a Co-Simulation FMU";
const NO_CLOCKS: &str = "ViscoSPH has no clocks";

unsupported!(fmi3EnterEventMode() -> fmi3Status, NO_EVENT_MODE);
unsupported!(fmi3EnterStepMode() -> fmi3Status, NO_EVENT_MODE);
unsupported!(
    fmi3EnterConfigurationMode() -> fmi3Status,
    "ViscoSPH has no structural parameters: there is no Configuration Mode"
);
unsupported!(
    fmi3ExitConfigurationMode() -> fmi3Status,
    "ViscoSPH has no structural parameters: there is no Configuration Mode"
);
unsupported!(
    fmi3GetNumberOfVariableDependencies(
        _valueReference: fmi3ValueReference,
        _nDependencies: *mut usize,
    ) -> fmi3Status,
    "dependencies are declared in modelDescription.xml's ModelStructure (providesPerElementDependencies = false)"
);
unsupported!(
    fmi3GetVariableDependencies(
        _dependent: fmi3ValueReference,
        _elementIndicesOfDependent: *mut usize,
        _independents: *mut fmi3ValueReference,
        _elementIndicesOfIndependents: *mut usize,
        _dependencyKinds: *mut fmi3DependencyKind,
        _nDependencies: usize,
    ) -> fmi3Status,
    "dependencies are declared in modelDescription.xml's ModelStructure (providesPerElementDependencies = false)"
);
unsupported!(
    fmi3GetDirectionalDerivative(
        _unknowns: *const fmi3ValueReference,
        _nUnknowns: usize,
        _knowns: *const fmi3ValueReference,
        _nKnowns: usize,
        _seed: *const fmi3Float64,
        _nSeed: usize,
        _sensitivity: *mut fmi3Float64,
        _nSensitivity: usize,
    ) -> fmi3Status,
    "directional derivatives are not provided (providesDirectionalDerivatives = false)"
);
unsupported!(
    fmi3GetAdjointDerivative(
        _unknowns: *const fmi3ValueReference,
        _nUnknowns: usize,
        _knowns: *const fmi3ValueReference,
        _nKnowns: usize,
        _seed: *const fmi3Float64,
        _nSeed: usize,
        _sensitivity: *mut fmi3Float64,
        _nSensitivity: usize,
    ) -> fmi3Status,
    "adjoint derivatives are not provided (providesAdjointDerivatives = false)"
);
unsupported!(
    fmi3GetOutputDerivatives(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _orders: *const fmi3Int32,
        _values: *mut fmi3Float64,
        _nValues: usize,
    ) -> fmi3Status,
    "output derivatives are not provided (maxOutputDerivativeOrder = 0)"
);
unsupported!(
    fmi3ActivateModelPartition(
        _clockReference: fmi3ValueReference,
        _activationTime: fmi3Float64,
    ) -> fmi3Status,
    "Scheduled Execution is not supported: ViscoSPH is a Co-Simulation FMU"
);
unsupported!(
    fmi3GetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _intervals: *mut fmi3Float64,
        _qualifiers: *mut fmi3IntervalQualifier,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3GetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *mut fmi3UInt64,
        _resolutions: *mut fmi3UInt64,
        _qualifiers: *mut fmi3IntervalQualifier,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3GetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _shifts: *mut fmi3Float64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3GetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *mut fmi3UInt64,
        _resolutions: *mut fmi3UInt64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3SetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _intervals: *const fmi3Float64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3SetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *const fmi3UInt64,
        _resolutions: *const fmi3UInt64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3SetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _shifts: *const fmi3Float64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(
    fmi3SetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *const fmi3UInt64,
        _resolutions: *const fmi3UInt64,
    ) -> fmi3Status,
    NO_CLOCKS
);
unsupported!(fmi3EvaluateDiscreteStates() -> fmi3Status, NO_EVENT_MODE);
unsupported!(
    fmi3UpdateDiscreteStates(
        _discreteStatesNeedUpdate: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean,
        _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
        _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
        _nextEventTimeDefined: *mut fmi3Boolean,
        _nextEventTime: *mut fmi3Float64,
    ) -> fmi3Status,
    NO_EVENT_MODE
);
unsupported!(fmi3EnterContinuousTimeMode() -> fmi3Status, NO_ME);
unsupported!(
    fmi3CompletedIntegratorStep(
        _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
        _enterEventMode: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean,
    ) -> fmi3Status,
    NO_ME
);
unsupported!(fmi3SetTime(_time: fmi3Float64) -> fmi3Status, NO_ME);
unsupported!(
    fmi3SetContinuousStates(_continuousStates: *const fmi3Float64, _nContinuousStates: usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetContinuousStateDerivatives(_derivatives: *mut fmi3Float64, _nContinuousStates: usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetEventIndicators(_eventIndicators: *mut fmi3Float64, _nEventIndicators: usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetContinuousStates(_continuousStates: *mut fmi3Float64, _nContinuousStates: usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetNominalsOfContinuousStates(_nominals: *mut fmi3Float64, _nContinuousStates: usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetNumberOfEventIndicators(_nEventIndicators: *mut usize) -> fmi3Status,
    NO_ME
);
unsupported!(
    fmi3GetNumberOfContinuousStates(_nContinuousStates: *mut usize) -> fmi3Status,
    NO_ME
);
