//! Particle snapshots as legacy VTK polydata (ASCII), readable by ParaView and VisIt.

use std::io::Write;
use std::path::Path;

/// The third coordinate: "0" as a 2D file always wrote it, else in full.
fn xyz_z(z: f64) -> String {
    if z == 0.0 {
        "0".into()
    } else {
        format!("{z:.9e}")
    }
}

/// One named scalar field per particle.
pub struct Field<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
}

/// Write points (a 2D run's at z = 0) with vertex cells, a velocity vector field and scalar
/// fields.
pub fn write_particles(
    path: &Path,
    positions: &[[f64; 3]],
    velocities: &[[f64; 3]],
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
        writeln!(w, "{:.9e} {:.9e} {}", p[0], p[1], xyz_z(p[2]))?;
    }
    writeln!(w, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(w, "1 {i}")?;
    }
    writeln!(w, "POINT_DATA {n}")?;
    writeln!(w, "VECTORS velocity double")?;
    for v in velocities {
        writeln!(w, "{:.9e} {:.9e} {}", v[0], v[1], xyz_z(v[2]))?;
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
