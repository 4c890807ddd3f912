//! The docs say what holds now: no history ("session N", "issue N", "superseded"), no
//! placeholder values, in README.md and every markdown file under docs/ (the user manual's
//! sources included, its rendered output in docs/book/book/ not). History is in git.

use std::path::{Path, PathBuf};

fn markdown_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut dirs = vec![root.join("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.unwrap().path();
            if path.is_dir() {
                // The rendered book (mdbook's build directory) is not a source.
                if path != root.join("docs/book/book") {
                    dirs.push(path);
                }
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// What a line may not say, or None: a session or issue number, a superseded table, a
/// placeholder.
fn forbidden(line: &str) -> Option<&'static str> {
    let lower = line.to_lowercase();
    if lower.contains("session") {
        return Some("\"session\": history belongs in git");
    }
    if lower.contains("superseded") {
        return Some("\"superseded\": drop the old figures, git keeps them");
    }
    let bytes = lower.as_bytes();
    for (k, _) in lower.match_indices("issue") {
        let rest = &bytes[k + 5..];
        let digits = rest.iter().skip_while(|&&c| c == b' ' || c == b'#');
        if rest.first().is_some_and(|&c| c == b' ' || c == b'#')
            && digits.clone().next().is_some_and(|c| c.is_ascii_digit())
        {
            return Some("\"issue N\": say what holds, not which issue did it");
        }
    }
    for word in [
        "todo",
        "tbd",
        "fixme",
        "xxx",
        "placeholder",
        "not run yet",
        "lorem ipsum",
        "???",
    ] {
        let hit = lower.match_indices(word).any(|(k, _)| {
            // Whole words only ("todo" in "mastodon" is fine).
            let before = lower[..k].chars().next_back();
            let after = lower[k + word.len()..].chars().next();
            !before.is_some_and(|c| c.is_alphanumeric())
                && !after.is_some_and(|c| c.is_alphanumeric())
        });
        if hit {
            return Some("a placeholder");
        }
    }
    None
}

/// Cells of a markdown table row (without the outer pipes; escaped pipes stay in their cell).
fn cells(row: &str) -> Vec<String> {
    let inner = row.trim().trim_start_matches('|').trim_end_matches('|');
    let mut out = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\\' && chars.peek() == Some(&'|') {
            out.last_mut().unwrap().push('|');
            chars.next();
        } else if c == '|' {
            out.push(String::new());
        } else {
            out.last_mut().unwrap().push(c);
        }
    }
    out.into_iter().map(|c| c.trim().to_string()).collect()
}

/// A resolution column (particles per diameter, across, W/dr) holds a resolution: a whole
/// number below 1000 (a note may follow it), or "-". A value such as 100000 there is a row pasted into the wrong table.
fn bad_resolutions(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut bad = Vec::new();
    let mut k = 0;
    while k + 1 < lines.len() {
        let separator = lines[k + 1].trim_start();
        let is_table = lines[k].trim_start().starts_with('|')
            && (separator.starts_with("|--") || separator.starts_with("| --"));
        if !is_table {
            k += 1;
            continue;
        }
        let header = cells(lines[k]);
        let columns: Vec<usize> = header
            .iter()
            .enumerate()
            .filter(|(_, h)| {
                let h = h.to_lowercase();
                h == "particles/d"
                    || h == "particles/diameter"
                    || h == "particles/w"
                    || h == "particles_per_diameter"
                    || h == "across"
                    || h == "w/dr"
            })
            .map(|(i, _)| i)
            .collect();
        let mut r = k + 2;
        while r < lines.len() && lines[r].trim_start().starts_with('|') {
            let row = cells(lines[r]);
            for &c in &columns {
                if let Some(v) = row.get(c) {
                    // A note may follow the number ("40, time_step_factor 0.1").
                    let lead: String = v.chars().take_while(|c| c.is_ascii_digit()).collect();
                    let ok = v == "-" || lead.parse::<u32>().is_ok_and(|n| n < 1000);
                    if !ok {
                        bad.push(format!("line {}: '{}' in column '{}'", r + 1, v, header[c]));
                    }
                }
            }
            r += 1;
        }
        k = r;
    }
    bad
}

#[test]
fn docs_say_what_holds_now() {
    let files = markdown_files();
    assert!(files.len() >= 6, "{files:?}");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let name = f.strip_prefix(root).unwrap().display().to_string();
        for (n, line) in text.lines().enumerate() {
            if let Some(why) = forbidden(line) {
                found.push(format!("{name}:{}: {why}: {}", n + 1, line.trim()));
            }
        }
        for b in bad_resolutions(&text) {
            found.push(format!("{name}: placeholder value: {b}"));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn the_checks_catch_what_they_are_for() {
    assert!(forbidden("### Issue 16, fifth session: the ceiling").is_some());
    assert!(forbidden("measured before issue 12's fixes").is_some());
    assert!(forbidden("see issue #35").is_some());
    assert!(forbidden("Earlier measurements (superseded by the section above)").is_some());
    assert!(forbidden("| wcsph | TODO |").is_some());
    assert!(forbidden("the issue here is the time step").is_none());
    assert!(forbidden("issues a warning at 10 steps").is_none());
    assert!(forbidden("a co-simulation master").is_none());
    let table = "| scheme | case | particles/D | wall time [s] |\n|---|---|---|---|\n\
                 | isph | oldroyd_b | 40 | 27.41 |\n| isph | oldroyd_b | 100000 | 100000 |\n";
    assert_eq!(
        bad_resolutions(table).len(),
        1,
        "{:?}",
        bad_resolutions(table)
    );
    let escaped = "| a \\| b | across |\n|---|---|\n| x \\| y | 30 |\n";
    assert!(bad_resolutions(escaped).is_empty());
}
