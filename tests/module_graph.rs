//! The library's top-level modules form a layered graph: no module reaches, through `crate::`
//! paths in its code, a module that reaches back to it (directly or through others). A cycle
//! makes two modules one piece that can only be understood and changed together; it is how the
//! solver core tangled before the architecture issue. Comments and `#[cfg(test)]` code are not
//! counted (a test may use anything).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The files and folders of modules declared under `#[cfg(test)]` (`#[cfg(test)] mod x;` in
/// `dir/mod.rs` or `dir.rs` names `dir/x.rs` and `dir/x/`): test code, whatever its file name.
fn test_modules(files: &[PathBuf]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(f).unwrap();
        let dir = match f.file_name().unwrap().to_str().unwrap() {
            "mod.rs" | "lib.rs" | "main.rs" => f.parent().unwrap().to_path_buf(),
            _ => f.with_extension(""),
        };
        let mut lines = text.lines().map(str::trim);
        while let Some(line) = lines.next() {
            if line != "#[cfg(test)]" {
                continue;
            }
            let next = lines.next().unwrap_or("");
            if let Some(name) = next
                .strip_prefix("mod ")
                .or_else(|| next.strip_prefix("pub mod "))
                .or_else(|| next.strip_prefix("pub(crate) mod "))
                .and_then(|r| r.strip_suffix(';'))
            {
                out.push(dir.join(format!("{name}.rs")));
                out.push(dir.join(name));
            }
        }
    }
    out
}

/// Edges module -> modules it names through `crate::` in non-test, non-comment code.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let tests = test_modules(&files);
    let module_of = |p: &Path| -> Option<String> {
        let rel = p.strip_prefix(&src).unwrap();
        let first = rel.components().next()?.as_os_str().to_str()?.to_string();
        let name = first.trim_end_matches(".rs").to_string();
        (name != "lib" && name != "main" && name != "bin").then_some(name)
    };
    let modules: BTreeSet<String> = files.iter().filter_map(|p| module_of(p)).collect();
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let Some(m) = module_of(f) else { continue };
        if tests.iter().any(|t| f.starts_with(t)) {
            continue;
        }
        if f.file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .ends_with("_tests.rs")
        {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap();
        for line in code.lines() {
            let line = line.trim_start();
            if line.starts_with("//") {
                continue;
            }
            for (k, _) in line.match_indices("crate::") {
                let rest = &line[k + "crate::".len()..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name != m && modules.contains(&name) {
                    g.entry(m.clone()).or_default().insert(name);
                }
            }
        }
        g.entry(m).or_default();
    }
    g
}

#[test]
fn top_level_modules_have_no_cycle() {
    let g = graph();
    // Depth-first search for a back edge; report the cycle found.
    fn visit(
        m: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        path.push(m.to_string());
        for n in g.get(m).into_iter().flatten() {
            match state.get(n.as_str()).copied().unwrap_or(0) {
                1 => {
                    let at = path.iter().position(|p| p == n).unwrap();
                    let mut cycle = path[at..].to_vec();
                    cycle.push(n.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(n, g, state, path) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in g.keys() {
        if state.get(m.as_str()).copied().unwrap_or(0) == 0 {
            let cycle = visit(m, &g, &mut state, &mut Vec::new());
            assert!(
                cycle.is_none(),
                "module cycle: {}",
                cycle.unwrap().join(" -> ")
            );
        }
    }
}

#[test]
fn the_lower_layers_depend_on_nothing_above_them() {
    // The dimension is the bottom layer. The constitutive models, the kernels and the neighbour
    // search are leaves above it: they can be tested and reused alone. The state depends only
    // on the dimension, particles and wall geometry.
    let g = graph();
    let allowed: &[(&str, &[&str])] = &[
        ("dim", &[]),
        ("rheology", &["choice", "dim"]),
        ("kernel", &[]),
        ("neighbors", &["dim"]),
        ("particles", &["dim"]),
        ("state", &["boundary", "dim", "particles"]),
    ];
    for (m, ok) in allowed {
        let deps = g.get(*m).unwrap_or_else(|| panic!("no module {m}"));
        for d in deps {
            assert!(ok.contains(&d.as_str()), "{m} depends on {d}");
        }
    }
    // The detection works: the simulation does depend on the scheme.
    assert!(g["simulation"].contains("scheme"));
}
