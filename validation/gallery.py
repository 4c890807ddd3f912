"""docs/book/src/validation.md, the book's gallery page, from the cases' READMEs, figures and
results.md (run by `validation/run.sh` after the full runs). A case is every directory of
validation/ with a README.md; its figure is <case>.png (or the first PNG of its reference/)."""
import shutil
from pathlib import Path

HERE = Path(__file__).resolve().parent
BOOK = HERE.parent / "docs" / "book" / "src"


def intro(readme):
    """The README's title and its first paragraph."""
    lines = readme.read_text().split("\n\n")
    title = lines[0].lstrip("# ").strip()
    first = next((p for p in lines[1:] if p.strip() and not p.startswith(("|", "#", "```"))),
                 "")
    return title, " ".join(first.split())


def main():
    figures = BOOK / "validation"
    figures.mkdir(parents=True, exist_ok=True)
    page = ["# Validation gallery", "",
            "Each case below lives in `validation/<case>/` of the repository: its scene files, "
            "the reference with its source, `run.py` (runs the case through `viscosph run` and "
            "draws the comparison), the figure and `results.md` (the measured errors, the "
            "thresholds of the case's README and the commit). `bash validation/run.sh` runs "
            "every case at the README's resolution and writes this page; `bash validation/run.sh "
            "--short` runs them at low resolution, as the test command does, and fails when an "
            "error breaks its README's threshold.", ""]
    for case in sorted(p for p in HERE.iterdir() if (p / "README.md").exists()):
        title, first = intro(case / "README.md")
        png = case / f"{case.name}.png"
        if not png.exists():
            png = next(iter(sorted((case / "reference").glob("*.png"))), None)
        page += [f"## {title}", "", first, ""]
        if png is not None:
            shutil.copy(png, figures / f"{case.name}.png")
            page += [f"![{case.name}](validation/{case.name}.png)", ""]
        results = case / "results.md"
        if results.exists():
            page += [results.read_text().strip(), ""]
        page += [f"The case, its reference and thresholds: `validation/{case.name}/README.md`.",
                 ""]
    (BOOK / "validation.md").write_text("\n".join(page))
    print(f"wrote {BOOK / 'validation.md'}")


if __name__ == "__main__":
    main()
