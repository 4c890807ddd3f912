//! What a run of the jet says about buckling: when the jet reached the plate, when it started to
//! buckle, how fast and how far it swings ([`buckling`], from the record of `jet_deflection`),
//! and the summary line `viscosph run` prints.

use super::{Outputs, Predictions, SceneConfig};

/// What a record of `jet_deflection` says about buckling (see [`buckling`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Buckling {
    /// When the jet first reached the plate (the heap first had a height) \[s\]; None if never.
    pub impact: Option<f64>,
    /// First time after impact that |jet_deflection| exceeded [`ONSET_FRACTION`] D \[s\].
    pub onset: Option<f64>,
    /// Half the peak-to-peak range of `jet_deflection` over the second half of the record after
    /// impact \[m\].
    pub amplitude: f64,
    /// Frequency of the oscillation after onset: mean-crossings of the deflection over twice
    /// the time they span \[Hz\]; 0 with fewer than three crossings. Onset, amplitude and
    /// frequency leave out the outputs at which no fluid was in the band (`jet_deflection`
    /// exactly 0, a gap of a torn column).
    pub frequency: f64,
}

/// Deflection, as a fraction of the jet width, beyond which the jet counts as buckled.
pub const ONSET_FRACTION: f64 = 0.1;

/// Onset, amplitude and frequency of buckling from a record of outputs of a jet of width `d`.
pub fn buckling(series: &[(f64, Outputs)], d: f64) -> Buckling {
    let Some(k0) = series.iter().position(|(_, o)| o.shared.drop_height > 0.0) else {
        return Buckling::default();
    };
    // Outputs at which no fluid was in the measuring band (`jet_deflection` exactly 0: a torn
    // column's gap passing the band) say nothing about the column's position: left out, as
    // each would otherwise count as two mean crossings (measured: ISPH's torn Oldroyd-B
    // columns at 6 across read 40-50 Hz with them).
    let impact = Some(series[k0].0);
    let after: Vec<&(f64, Outputs)> = series[k0..]
        .iter()
        .filter(|(_, o)| o.jet.jet_deflection != 0.0)
        .collect();
    if after.is_empty() {
        return Buckling {
            impact,
            ..Buckling::default()
        };
    }
    let onset = after
        .iter()
        .find(|(_, o)| o.jet.jet_deflection.abs() > ONSET_FRACTION * d)
        .map(|(t, _)| *t);
    let late = &after[after.len() / 2..];
    let (lo, hi) = late
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, o)| {
            (lo.min(o.jet.jet_deflection), hi.max(o.jet.jet_deflection))
        });
    let amplitude = if lo.is_finite() { 0.5 * (hi - lo) } else { 0.0 };
    let mut frequency = 0.0;
    if let Some(t_on) = onset {
        let tail: Vec<(f64, f64)> = after
            .iter()
            .filter(|(t, _)| *t >= t_on)
            .map(|(t, o)| (*t, o.jet.jet_deflection))
            .collect();
        let mean = tail.iter().map(|p| p.1).sum::<f64>() / tail.len() as f64;
        let crossings: Vec<f64> = tail
            .windows(2)
            .filter(|w| (w[0].1 - mean) * (w[1].1 - mean) < 0.0)
            .map(|w| {
                let (a, b) = (w[0].1 - mean, w[1].1 - mean);
                w[0].0 + (w[1].0 - w[0].0) * a / (a - b)
            })
            .collect();
        if crossings.len() >= 3 {
            let span = crossings[crossings.len() - 1] - crossings[0];
            frequency = (crossings.len() - 1) as f64 / (2.0 * span);
        }
    }
    Buckling {
        impact,
        onset,
        amplitude,
        frequency,
    }
}

/// The line `viscosph run` prints about a jet: the mass injected, when the jet reached the plate
/// (and when a model outside the solver says it does: the slender-sheet model's, or the
/// round jet's slender-thread model's, "arrival_time", if the caller has it), and how it buckled.
pub fn summary(
    cfg: &SceneConfig,
    series: &[(f64, Outputs)],
    predictions: &dyn Predictions,
) -> String {
    let d = cfg.jet.jet_width;
    let b = buckling(series, d);
    let injected = series.last().map_or(0.0, |s| s.1.jet.injected_mass);
    let unit = if cfg.numerics.dimension == 3 { "kg" } else { "kg/m" };
    let mut text = format!("injected mass {injected:.4e} {unit}; ");
    let Some(impact) = b.impact else {
        text.push_str("the jet has not reached the plate");
        return text;
    };
    text.push_str(&format!("the jet reached the plate at t = {impact:.4} s"));
    if let Some(p) = predictions.predict(cfg, "arrival_time") {
        text.push_str(&format!(" (the {}'s arrival: {:.4} s)", p.model, p.value));
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
    text
}

/// When the fluid's lowest point (`jet_tip_height`) first came within `height` of the plate,
/// interpolated linearly between the outputs; None if it never did.
///
/// The slender sheet and thread leave the plate out: their arrival is the time their free end,
/// the fluid's lowest point, has fallen the nozzle height. An SPH head feels the plate from
/// about two spacings above it (its kernel reaches the wall's particles) and then creeps the
/// last half spacing, so that its contact (`height` = dx/2: the lowest particle's centre within
/// one spacing) depends on the resolution through the plate's reach. The fall itself is
/// compared where the plate is not yet felt: `height` = D/2, against the model's time to fall
/// the nozzle height less D/2 (the same definition on both sides).
pub fn arrival(series: &[(f64, Outputs)], height: f64) -> Option<f64> {
    let k = series
        .iter()
        .position(|(_, o)| o.jet.jet_tip_height <= height)?;
    if k == 0 {
        return Some(series[0].0);
    }
    let ((t0, a), (t1, b)) = (
        (series[k - 1].0, series[k - 1].1.jet.jet_tip_height),
        (series[k].0, series[k].1.jet.jet_tip_height),
    );
    Some(t0 + (t1 - t0) * (a - height) / (a - b))
}

/// The line `viscosph run` prints about a round jet (`dimension = 3`): the mass injected \[kg\];
/// the fall ([`arrival`]): when the lowest point passed D/2 above the plate (and the slender
/// thread's time to fall as far, if the caller has it) and when it reached the plate (within
/// half a spacing); how far the column leaned along x (`jet_deflection`); and whether it
/// coiled: the first output after contact at which `jet_coil_radius` passed
/// [`ONSET_FRACTION`] D, the share of the outputs since at which it was above, the radius (mean
/// over the second half of the outputs since) and `jet_coil_frequency` at the end.
pub fn summary_3d(
    cfg: &SceneConfig,
    series: &[(f64, Outputs)],
    predictions: &dyn Predictions,
) -> String {
    let d = cfg.jet.jet_width;
    let injected = series.last().map_or(0.0, |s| s.1.jet.injected_mass);
    let mut text = format!("injected mass {injected:.4e} kg; ");
    let Some(t_arr) = arrival(series, 0.5 * cfg.dx()) else {
        text.push_str("the jet has not reached the plate");
        return text;
    };
    if let Some(t_half) = arrival(series, 0.5 * d) {
        text.push_str(&format!(
            "the jet's lowest point passed D/2 above the plate at t = {t_half:.4} s"
        ));
        let mut above = cfg.clone();
        above.jet.nozzle_height -= 0.5 * d;
        if let Some(p) = predictions.predict(&above, "arrival_time") {
            text.push_str(&format!(
                " (the {}'s: {:.4} s, {:+.1} %)",
                p.model,
                p.value,
                100.0 * (t_half / p.value - 1.0)
            ));
        }
        text.push_str(", and ");
    }
    text.push_str(&format!(
        "the jet reached the plate at t = {t_arr:.4} s (its lowest point within half a spacing)"
    ));
    let after: Vec<&(f64, Outputs)> = series.iter().filter(|(t, _)| *t >= t_arr).collect();
    let lean = after
        .iter()
        .map(|(_, o)| o.jet.jet_deflection.abs())
        .fold(0.0, f64::max);
    text.push_str(&format!(
        "; largest |jet_deflection| since {lean:.3e} m = {:.3} D; ",
        lean / d
    ));
    let Some(k0) = after
        .iter()
        .position(|(_, o)| o.jet.jet_coil_radius > ONSET_FRACTION * d)
    else {
        text.push_str(&format!(
            "no coil (jet_coil_radius stayed below {ONSET_FRACTION} D)"
        ));
        return text;
    };
    let coiled = &after[k0..];
    let late = &coiled[coiled.len() / 2..];
    let radius = late.iter().map(|(_, o)| o.jet.jet_coil_radius).sum::<f64>() / late.len() as f64;
    let off = coiled
        .iter()
        .filter(|(_, o)| o.jet.jet_coil_radius > ONSET_FRACTION * d)
        .count();
    let frequency = coiled.last().map_or(0.0, |(_, o)| o.jet.jet_coil_frequency);
    text.push_str(&format!(
        "the column left the axis at t = {:.4} s and was off it ({ONSET_FRACTION} D) at {:.0} % \
         of the outputs since: coil radius {radius:.3e} m = {:.3} D (mean over the second half \
         of them), coil frequency {frequency:.2} Hz at the end",
        coiled[0].0,
        100.0 * off as f64 / coiled.len() as f64,
        radius / d
    ));
    text
}

#[cfg(test)]
mod tests {
    use super::super::JetOutputs;
    use super::*;

    #[test]
    fn buckling_of_a_sine_after_impact() {
        // Impact at t = 0.1 s, then a 5 Hz oscillation of amplitude 2 mm growing in within
        // 0.05 s: onset when it passes 0.6 mm, frequency 5 Hz, amplitude 2 mm.
        let d = 0.006;
        let series: Vec<(f64, Outputs)> = (0..=1000)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let mut o = Outputs::default();
                if t >= 0.1 {
                    o.shared.drop_height = 0.001;
                    let ramp = ((t - 0.1) / 0.05).min(1.0);
                    o.jet.jet_deflection =
                        0.002 * ramp * (2.0 * std::f64::consts::PI * 5.0 * (t - 0.1)).sin();
                }
                (t, o)
            })
            .collect();
        let b = buckling(&series, d);
        assert_eq!(b.impact, Some(0.1));
        let onset = b.onset.unwrap();
        assert!(onset > 0.1 && onset < 0.15, "{onset}");
        assert!((b.amplitude - 0.002).abs() < 1e-5, "{}", b.amplitude);
        assert!((b.frequency - 5.0).abs() < 0.05, "{}", b.frequency);
        // A straight jet: no onset, no frequency.
        let straight: Vec<(f64, Outputs)> = series
            .iter()
            .map(|(t, o)| {
                (
                    *t,
                    Outputs {
                        jet: JetOutputs {
                            jet_deflection: 1e-5,
                            ..o.jet
                        },
                        ..*o
                    },
                )
            })
            .collect();
        let b = buckling(&straight, d);
        assert_eq!((b.onset, b.frequency, b.amplitude), (None, 0.0, 0.0));
    }

    #[test]
    fn outputs_without_fluid_in_the_band_do_not_count_as_crossings() {
        // A column buckling about an offset of 1 mm (the heap's side) at 5 Hz, torn: every
        // seventh output finds no fluid in the band (jet_deflection exactly 0). With those
        // outputs read as positions, each would be two crossings of the mean.
        let d = 0.006;
        let record = |gaps: bool| -> Vec<(f64, Outputs)> {
            (0..=1000)
                .map(|k| {
                    let t = k as f64 * 1e-3;
                    let mut o = Outputs::default();
                    if t >= 0.1 {
                        o.shared.drop_height = 0.001;
                        o.jet.jet_deflection = if gaps && k % 7 == 0 {
                            0.0
                        } else {
                            0.001 + 0.002 * (2.0 * std::f64::consts::PI * 5.0 * (t - 0.1)).sin()
                        };
                    }
                    (t, o)
                })
                .collect()
        };
        let whole = buckling(&record(false), d);
        let torn = buckling(&record(true), d);
        println!("{whole:?}\n{torn:?}");
        assert!((whole.frequency - 5.0).abs() < 0.05, "{whole:?}");
        assert!((torn.frequency - 5.0).abs() < 0.05, "{torn:?}");
        assert_eq!(torn.impact, Some(0.1));
        assert!((torn.amplitude - 0.002).abs() < 1e-4, "{torn:?}");
    }
}
