//! Smoke test of `viscosph bench channel --quick`: every part runs and writes CSV, Markdown and
//! PNG files of the right structure with sane values. The measured figures are the benchmark's
//! own (docs/benchmarks.md); only what must hold at any resolution is asserted here.

use std::path::Path;
use std::process::Command;

fn rows(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    (
        header,
        lines
            .map(|l| l.split(',').map(String::from).collect())
            .collect(),
    )
}

fn png(path: &Path) {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&b[1..4], b"PNG", "{}", path.display());
}

#[test]
fn channel_bench_quick() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    let o = Command::new(env!("CARGO_BIN_EXE_viscosph"))
        .args(["bench", "channel", "--quick", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("channel.md")).unwrap();
    for part in ["### (a)", "### (b)", "### (c)"] {
        assert!(md.contains(part), "{part} missing from channel.md");
    }

    // (a) Both schemes at both resolutions; the finer one is closer to Waters & King.
    let (h, r) = rows(&out.join("channel_accuracy.csv"));
    assert_eq!((h[0].as_str(), h[5].as_str()), ("scheme", "l2_rms"));
    for scheme in ["wcsph", "pdri"] {
        let errs: Vec<f64> = r
            .iter()
            .filter(|x| x[0] == scheme)
            .map(|x| x[5].parse().unwrap())
            .collect();
        assert_eq!(errs.len(), 2, "{scheme}");
        assert!(errs.iter().all(|e| e.is_finite() && *e > 0.0 && *e < 0.2));
        assert!(errs[1] < errs[0], "{scheme}: {errs:?}");
    }
    png(&out.join("channel_accuracy.png"));

    // (b) Every run either passed or says why not; the sweeps start at Wi = 1.
    let (h, r) = rows(&out.join("channel_wi.csv"));
    assert_eq!((h[5].as_str(), h[6].as_str()), ("wi", "passed"));
    assert!(!r.is_empty());
    for x in &r {
        assert!(
            x[6] == "true" || !x[10].is_empty(),
            "a failed run without a cause: {x:?}"
        );
    }
    assert!(r.iter().any(|x| x[5] == "1"));
    assert!(md.contains("largest stable Wi"));
    png(&out.join("channel_wi.png"));

    // (c) Finite errors against the steady solutions.
    let (h, r) = rows(&out.join("channel_nonlinear.csv"));
    assert_eq!(h[5], "l2_u");
    assert!(r.iter().any(|x| x[1] == "fene_cr"));
    for x in &r {
        let e: f64 = x[5].parse().unwrap();
        assert!(e.is_finite() && e >= 0.0, "{x:?}");
    }
    png(&out.join("channel_nonlinear.png"));
}
