//! `viscosph` draws the text of its PNGs with the font compiled into it (src/io/plot.rs): on a
//! server without fonts, here an empty fontconfig configuration, a run still writes both PNGs
//! with their titles drawn, and the binary links neither fontconfig nor freetype.

use std::process::Command;

/// Pixels darker than mid-grey in every channel among the rows `rows` of `png`: text (and, lower
/// down, axes and lines); the background is white.
fn dark_pixels(png: &std::path::Path, rows: std::ops::Range<u32>) -> usize {
    let img = image::open(png)
        .unwrap_or_else(|e| panic!("{}: {e}", png.display()))
        .to_rgb8();
    assert!(
        img.width() > 400 && img.height() > rows.end,
        "{}",
        png.display()
    );
    rows.flat_map(|y| (0..img.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x, y).0.iter().all(|&c| c < 128))
        .count()
}

#[test]
fn a_run_draws_its_pngs_without_any_installed_font() {
    let dir = tempfile::tempdir().unwrap();
    // A configuration that names no font directory: fontconfig finds no font at all (main's
    // binary, which drew through fontconfig, failed here with "No such font: sans-serif").
    let conf = dir.path().join("fonts.conf");
    std::fs::write(
        &conf,
        "<?xml version=\"1.0\"?>\n<!DOCTYPE fontconfig SYSTEM \"fonts.dtd\">\n<fontconfig></fontconfig>\n",
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let out = Command::new(env!("CARGO_BIN_EXE_viscosph"))
        .args([
            "run",
            "--t-end",
            "0.02",
            "--output-interval",
            "0.002",
            "--out",
        ])
        .arg(&out_dir)
        .env("FONTCONFIG_FILE", &conf)
        .env("FONTCONFIG_PATH", dir.path())
        .env("HOME", dir.path())
        .env("XDG_DATA_HOME", dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The title band of each PNG holds only text: thousands of dark pixels when it is drawn.
    for (png, title_rows) in [("width_height.png", 0..34), ("particles.png", 0..50)] {
        let n = dark_pixels(&out_dir.join(png), title_rows);
        assert!(n > 1000, "{png}: {n} dark pixels in the title band");
    }
}

#[test]
#[cfg(target_os = "linux")]
fn the_binary_links_no_font_library() {
    let out = Command::new("ldd")
        .arg(env!("CARGO_BIN_EXE_viscosph"))
        .output()
        .expect("ldd runs");
    let libs = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && libs.contains("libc.so"), "{libs}");
    for font_lib in ["libfontconfig", "libfreetype"] {
        assert!(
            !libs.contains(font_lib),
            "viscosph links {font_lib}:\n{libs}"
        );
    }
}
