//! What `viscosph run` says about a jet: when it reached the plate and how it buckled, from the
//! record of `jet_deflection` ([`viscosph::scene::jet::buckling`]), and when the slender-sheet
//! model ([`viscosph_reference::analytic::falling_sheet`]) says a jet of that fluid reaches it.

use viscosph::config::Scene;
use viscosph::diagnostics::Outputs;
use viscosph::scene::jet::{buckling, ONSET_FRACTION};
use viscosph::SceneConfig;
use viscosph_reference::analytic::falling_sheet;

/// Lines describing the buckling of a jet run (None for other scenes).
pub fn summary(cfg: &SceneConfig, series: &[(f64, Outputs)]) -> Option<String> {
    if cfg.scene != Scene::Jet {
        return None;
    }
    let d = cfg.jet_width;
    let b = buckling(series, d);
    let injected = series.last().map_or(0.0, |s| s.1.injected_mass);
    let mut text = format!("injected mass {injected:.4e} kg/m; ");
    let Some(impact) = b.impact else {
        text.push_str("the jet has not reached the plate");
        return Some(text);
    };
    text.push_str(&format!("the jet reached the plate at t = {impact:.4} s"));
    if let Some(sheet) = falling_sheet::arrival(cfg, falling_sheet::ELEMENTS_PER_WIDTH, 10.0) {
        text.push_str(&format!(
            " (the slender-sheet model's arrival: {:.4} s)",
            sheet.time
        ));
    }
    text.push_str("; ");
    match b.onset {
        None => text.push_str(&format!(
            "no buckling (jet_deflection stayed below {ONSET_FRACTION} D; amplitude {:.3e} m = \
             {:.3} D)",
            b.amplitude,
            b.amplitude / d
        )),
        Some(t) => text.push_str(&format!(
            "buckling onset at t = {t:.4} s, frequency {}, amplitude {:.3e} m = {:.3} D \
             (half the range of jet_deflection over the second half of the record after impact)",
            if b.frequency > 0.0 {
                format!("{:.2} Hz", b.frequency)
            } else {
                "- (fewer than three crossings)".to_string()
            },
            b.amplitude,
            b.amplitude / d
        )),
    }
    Some(text)
}
