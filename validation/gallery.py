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


def anchor(case):
    return case.name.replace("_", "-")


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
    cases = sorted(p for p in HERE.iterdir() if (p / "README.md").exists())
    page += ["| case | thresholds met (full runs) |", "|---|---|"]
    for case in cases:
        results = case / "results.md"
        if results.exists():
            text = results.read_text()
            met, broken = text.count("| pass |"), text.count("| FAIL |")
            verdict = f"{met} of {met + broken}" + (f", {broken} broken" if broken else "")
        else:
            verdict = "reference only"
        page.append(f"| [{intro(case / 'README.md')[0]}](#{anchor(case)}) | {verdict} |")
    page.append("")
    for case in cases:
        title, first = intro(case / "README.md")
        png = case / f"{case.name}.png"
        if not png.exists():
            png = next(iter(sorted((case / "reference").glob("*.png"))), None)
        page += [f"## {title} {{#{anchor(case)}}}", "", first, ""]
        if not (case / "run.py").exists():
            page += ["This case holds the reference only: the gallery does not run the SPH scene "
                     "against it.", ""]
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
