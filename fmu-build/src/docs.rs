//! `documentation/index.html` of the FMU (FMI 2.0 section 2.3: the documentation directory's
//! entry point), generated from the same tables as `modelDescription.xml`, so every variable,
//! unit, default and range shown is the one the binary enforces.

use viscosph::config::{range_text, Kind, Value};
use viscosph::fmi2::model_description::{
    escape, name_variable_description, name_variable_start, parameter_description,
    DEFAULT_STEP_SIZE, DEFAULT_STOP_TIME, LOG_CATEGORIES,
};
use viscosph::scene::OUTPUTS;
use viscosph::scene::{name_variables, SceneConfig, PARAMS};
use viscosph::Simulation;

/// Whether the default scene with `name` set to `item` can be built now, and if not, why.
fn availability(name: &str, item: &str) -> Result<(), String> {
    let mut cfg = SceneConfig::default();
    cfg.set(name, Value::Text(item.to_string()))
        .map_err(|e| e.to_string())?;
    Simulation::new(cfg).map(|_| ()).map_err(|e| e.to_string())
}

fn default_text(kind: &Kind) -> String {
    match *kind {
        Kind::Real { default, .. } => format!("{default}"),
        Kind::Integer { default, .. } => format!("{default}"),
        Kind::Enumeration { items, default, .. } => {
            let i = items.iter().position(|(n, _)| *n == default).unwrap_or(0) + 1;
            format!("{default} ({i})")
        }
    }
}

fn type_text(kind: &Kind) -> String {
    match kind {
        Kind::Real { .. } => "Real".into(),
        Kind::Integer { .. } => "Integer".into(),
        Kind::Enumeration { type_name, .. } => format!("Enumeration {type_name}"),
    }
}

const STYLE: &str = "body{font-family:sans-serif;max-width:70em;margin:2em auto;line-height:1.4}\
table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:.2em .5em;vertical-align:top}\
th{background:#eee}code,pre{background:#f6f6f6}pre{padding:.6em;overflow-x:auto}\
.no{color:#a00}";

/// The whole page; `platforms` are the binaries packed (e.g. `["linux64", "win64"]`).
pub fn index_html(platforms: &[&str]) -> String {
    let mut h = String::new();
    h.push_str(&format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>ViscoSPH.fmu</title><style>{STYLE}</style></head><body>\n"
    ));
    h.push_str(&format!(
        "<h1>ViscoSPH.fmu {}</h1>\n",
        env!("CARGO_PKG_VERSION")
    ));
    h.push_str(&format!(
        "<p>Binaries: {}.</p>\n",
        escape(&platforms.join(", "))
    ));
    h.push_str(
        "<p>An FMI 2.0 Co-Simulation FMU of transient viscoelastic and \
         shear-thinning free-surface flow, computed by Smoothed Particle Hydrodynamics in 2D. \
         The default experiment is the test case of Fang et al. (2006): a circular Oldroyd-B drop \
         of diameter 2 cm hits a rigid plate at 1 m/s (&eta;<sub>0</sub> = 4 Pa.s, \
         &beta; = 0.1, &lambda; = 0.02 s, Re = 5, We = 1), spreads, and retracts. The plate \
         may be inclined; the outputs are the drop's width and height, how far it reaches \
         downhill and uphill, and the force it exerts on the plate per unit depth.</p>\n",
    );
    h.push_str(&format!(
        "<p>Default experiment: 0 to {DEFAULT_STOP_TIME} s, communication step \
         {DEFAULT_STEP_SIZE} s. The scheme picks its own adaptive sub-steps and does not \
         shorten them to land on communication points: it steps past each one and the outputs \
         there are interpolated linearly between the two internal states around it. So the \
         trajectory, and the outputs to round-off, do not depend on the importer's step size, \
         which only sets how often the outputs are sampled (the time_step output is the \
         solver's own step).</p>\n"
    ));

    h.push_str("<h2>Worked example (fmpy)</h2>\n<pre>");
    h.push_str(&escape(WORKED_EXAMPLE));
    h.push_str("</pre>\n");

    h.push_str(
        "<h2>Coordinates</h2>\n<p>The impact point is where the vertical through the initial \
         drop centre meets the plate. The along-plate coordinate s is positive downhill (for a \
         level plate: +x). <code>wall_force_normal</code> is positive into the plate, \
         <code>wall_force_tangential</code> positive downhill.</p>\n",
    );

    h.push_str(
        "<h2>Parameters</h2>\n<p>All parameters have causality <code>parameter</code> and \
         variability <code>fixed</code>: set them before <code>fmi2ExitInitializationMode</code>. \
         A value outside its range is refused by <code>fmi2SetReal</code>/<code>fmi2SetInteger</code> \
         with <code>fmi2Error</code> and a log message naming the variable, the value and the \
         range; combinations that cannot be simulated (a drop starting inside the plate, a \
         resolution that would not fit in memory, a model not implemented yet) are refused by \
         <code>fmi2ExitInitializationMode</code>. Enumerations are set with \
         <code>fmi2SetInteger</code> to the item's number, or by name through their String \
         twin (<code>rheology_name = \"giesekus\"</code>, <code>fmi2SetString</code>), which \
         importers that ignore Enumerations (OSP libcosim, ecos) and fmpy's \
         <code>start_values</code> can set; the last value set wins.</p>\n",
    );
    h.push_str(
        "<table><tr><th>name</th><th>vr</th><th>type</th><th>unit</th><th>default</th>\
         <th>allowed</th><th>description</th></tr>\n",
    );
    for p in PARAMS.iter() {
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(p.name),
            p.value_reference,
            escape(&type_text(&p.kind)),
            escape(p.unit),
            escape(&default_text(&p.kind)),
            escape(&range_text(&p.kind)),
            escape(&parameter_description(p)),
        ));
    }
    for (p, name, vr) in name_variables() {
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{vr}</td><td>String</td><td></td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&name),
            escape(name_variable_start(p)),
            escape(&range_text(&p.kind)),
            escape(&name_variable_description(p)),
        ));
    }
    h.push_str("</table>\n");

    h.push_str("<h3>Enumeration items</h3>\n");
    for p in PARAMS.iter() {
        if let Kind::Enumeration {
            type_name, items, ..
        } = p.kind
        {
            h.push_str(&format!(
                "<h4><code>{}</code> (type {type_name})</h4>\n<table><tr><th>#</th><th>item</th>\
                 <th>meaning</th><th>available in this build</th></tr>\n",
                escape(p.name)
            ));
            for (i, (item, descr)) in items.iter().enumerate() {
                let avail = match availability(p.name, item) {
                    Ok(()) => "yes".to_string(),
                    Err(e) => format!("<span class=\"no\">no: {}</span>", escape(&e)),
                };
                h.push_str(&format!(
                    "<tr><td>{}</td><td><code>{}</code></td><td>{}</td><td>{avail}</td></tr>\n",
                    i + 1,
                    escape(item),
                    escape(descr)
                ));
            }
            h.push_str("</table>\n");
        }
    }

    h.push_str(
        "<h2>Outputs</h2>\n<p>Causality <code>output</code>, variability \
         <code>continuous</code>, initial <code>calculated</code>; readable from initialization \
         mode on. They are never NaN: after a numerical breakdown they keep the values of the \
         last good state.</p>\n<table><tr><th>name</th><th>vr</th><th>unit</th>\
         <th>description</th></tr>\n",
    );
    for o in OUTPUTS.iter() {
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(o.name),
            o.value_reference,
            escape(o.unit),
            escape(o.description)
        ));
    }
    h.push_str("</table>\n");

    h.push_str(
        "<h2>Co-simulation behaviour</h2>\n<ul>\
         <li><code>fmi2DoStep(t, h)</code> requires t to be the last communication point and \
         h &gt; 0; any h is accepted (canHandleVariableCommunicationStepSize).</li>\
         <li>A numerical breakdown (for example the tensile instability clumping particles) \
         answers <code>fmi2Discard</code> with a message naming the time and the cause; \
         <code>fmi2GetRealStatus(fmi2LastSuccessfulTime)</code> gives the time of the last good \
         state, whose outputs remain readable, and <code>fmi2GetBooleanStatus(fmi2Terminated)</code> \
         is true.</li>\
         <li>FMU states can be saved, restored, serialized and deserialized \
         (canGetAndSetFMUstate, canSerializeFMUstate); a serialized state holds no pointers and \
         restores in another process.</li>\
         <li>Several instances may live in one process and run on different threads; they \
         share nothing.</li>\
         <li>A call in the wrong state, a refused value or a failed initialization answers \
         <code>fmi2Error</code>, logs why, and leaves the instance in the error state, from \
         which <code>fmi2Reset</code>, <code>fmi2SetFMUstate</code> or \
         <code>fmi2FreeInstance</code> continue. Model-Exchange functions answer \
         <code>fmi2Error</code>.</li></ul>\n",
    );
    h.push_str(
        "<h3>Log categories</h3>\n<p>Without <code>loggingOn</code> only errors and discards \
         are reported; <code>fmi2SetDebugLogging</code> switches categories on and off.</p>\n\
         <table><tr><th>category</th><th>reports</th></tr>\n",
    );
    for (name, descr) in LOG_CATEGORIES {
        h.push_str(&format!(
            "<tr><td><code>{name}</code></td><td>{}</td></tr>\n",
            escape(descr)
        ));
    }
    h.push_str("</table>\n");

    h.push_str(METHODS);
    h.push_str("</body></html>\n");
    h
}

const WORKED_EXAMPLE: &str = r#"# pip install fmpy==0.3.* matplotlib
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException  # raised by fmpy for FMI 2.0 too
import matplotlib.pyplot as plt

fmu = "ViscoSPH.fmu"

res = simulate_fmu(
    fmu,
    stop_time=0.16,            # s
    output_interval=1e-3,      # communication step, s
    start_values={
        "plate_inclination": 30.0,      # deg
        "impact_velocity": 1.0,         # m/s
        "rheology_name": "oldroyd_b",  # or "rheology": 2, the item's number
        "particles_per_diameter": 20,
    },
    output=["drop_width", "drop_height", "spread_front", "spread_back",
            "wall_force_normal", "wall_force_tangential"],
)
plt.plot(res["time"], res["drop_width"], label="width [m]")
plt.plot(res["time"], res["spread_front"], label="downhill reach [m]")
plt.plot(res["time"], res["spread_back"], label="uphill reach [m]")
plt.legend(); plt.xlabel("t [s]"); plt.savefig("drop.png")

# a refused value raises; the FMU's log message says why
try:
    simulate_fmu(fmu, start_values={"plate_inclination": 95.0})
except FMICallException as e:
    print(e)   # the logger printed: parameter 'plate_inclination' = 95 is outside [0, 90)
"#;

const METHODS: &str = "<h2>Methods and papers</h2>\n<ul>\
<li><b>wcsph</b>: weakly compressible SPH after J. Fang, R. G. Owens, L. Tacher, A. Parriaux, \
<i>A numerical study of the SPH method for simulating transient viscoelastic free surface flows</i>, \
J. Non-Newtonian Fluid Mech. 139 (2006): cubic spline kernel (22), continuity (26), momentum (27), \
stress evolution (28), Monaghan artificial viscosity (30)-(37), artificial stress against the \
tensile instability (38)-(44), wall and image particles (46)-(48), predictor-corrector (49)-(50), \
time-step limits (51)-(53).</li>\
<li><b>pdri</b>: density-reinitialisation SPH after J. Ren, W. Lu, T. Jiang, <i>Numerical \
simulation of the generalized Newtonian free surface flows by a density reinitialization SPH \
method</i>, Math. Probl. Eng. (2015): MLS density reinitialisation (18a)-(18c), the Cross model \
(4)-(7), artificial stress (20a)-(20b), wall and ghost particles on an inclined plate \
(23a)-(23b).</li>\
<li><b>isph</b> and the constitutive models: J. R. C. King, S. J. Lind, <i>High Weissenberg \
number simulations with incompressible SPH and the log-conformation formulation</i> (2021): \
projection method, log-conformation (12)-(19), (29)-(33), EVSS (6)-(8), and the models of its \
Table I (Oldroyd-B, UCM, FENE-P, FENE-CR, linear and exponential PTT, Giesekus) as strain and \
relaxation functions.</li></ul>\n";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variable_unit_and_default_is_documented() {
        let html = index_html(&["linux64", "win64"]);
        for p in PARAMS.iter() {
            assert!(
                html.contains(&format!("<code>{}</code>", p.name)),
                "{}",
                p.name
            );
            assert!(html.contains(&escape(&default_text(&p.kind))), "{}", p.name);
            if !p.unit.is_empty() {
                assert!(
                    html.contains(&format!("<td>{}</td>", escape(p.unit))),
                    "{}",
                    p.unit
                );
            }
        }
        for o in OUTPUTS.iter() {
            assert!(
                html.contains(&format!("<code>{}</code>", o.name)),
                "{}",
                o.name
            );
        }
        assert!(html.contains("simulate_fmu"));
        assert!(html.contains("Fang") && html.contains("King") && html.contains("Ren"));
        assert!(
            html.contains("<td><code>oldroyd_b</code></td><td>Oldroyd-B</td><td>yes</td>"),
            "the default rheology is available"
        );
    }
}
