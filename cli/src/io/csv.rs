//! Time series as CSV: a `time` column, then one column per output (names as in the FMU).

use std::io::Write;
use std::path::Path;
use viscosph::scene::{Outputs, OUTPUTS};

/// Write `rows` of (time, outputs) to `path`.
pub fn write_timeseries(path: &Path, rows: &[(f64, Outputs)]) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(w, "time")?;
    for o in OUTPUTS.iter() {
        write!(w, ",{}", o.name)?;
    }
    writeln!(w)?;
    for (t, o) in rows {
        write!(w, "{t:.9e}")?;
        for v in o.values() {
            write!(w, ",{v:.9e}")?;
        }
        writeln!(w)?;
    }
    w.flush()
}

/// Read a time series written by [`write_timeseries`]: the header and the rows of numbers.
pub fn read_timeseries(path: &Path) -> std::io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    Ok((header, rows))
}
