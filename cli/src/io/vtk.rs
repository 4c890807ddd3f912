//! Particle snapshots as legacy VTK polydata (ASCII), readable by ParaView and VisIt.

use std::io::Write;
use std::path::Path;
use viscosph::Vec2;

/// One named scalar field per particle.
pub struct Field<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
}

/// Write points (z = 0) with vertex cells, a velocity vector field and scalar fields.
pub fn write_particles(
    path: &Path,
    positions: &[Vec2],
    velocities: &[Vec2],
    fields: &[Field<'_>],
) -> std::io::Result<()> {
    let n = positions.len();
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "# vtk DataFile Version 3.0")?;
    writeln!(w, "ViscoSPH particles")?;
    writeln!(w, "ASCII")?;
    writeln!(w, "DATASET POLYDATA")?;
    writeln!(w, "POINTS {n} double")?;
    for p in positions {
        writeln!(w, "{:.9e} {:.9e} 0", p.x, p.y)?;
    }
    writeln!(w, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(w, "1 {i}")?;
    }
    writeln!(w, "POINT_DATA {n}")?;
    writeln!(w, "VECTORS velocity double")?;
    for v in velocities {
        writeln!(w, "{:.9e} {:.9e} 0", v.x, v.y)?;
    }
    for f in fields {
        assert_eq!(f.values.len(), n, "field {} has the wrong length", f.name);
        writeln!(w, "SCALARS {} double 1", f.name)?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for v in f.values {
            writeln!(w, "{v:.9e}")?;
        }
    }
    w.flush()
}
