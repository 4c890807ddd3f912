#!/usr/bin/env bash
# The validation gallery: every validation/<case>/run.py, then (full mode) the book's page.
#   bash validation/run.sh --short   low resolution, about a minute: the test command's check;
#                                    results in target/validation/, the repository untouched
#   bash validation/run.sh           the READMEs' resolutions: each case's figure and results.md,
#                                    then docs/book/src/validation.md and its figures
# Uses the release binary target/release/viscosph (VISCOSPH_BIN overrides) and the Python of
# .venv (PYTHON overrides); builds nothing. Exit status 1 if any case breaks a threshold of its
# README (every case runs regardless).
set -uo pipefail
cd "$(dirname "$0")/.."
py=${PYTHON:-.venv/bin/python}
mode=()
case "${1:-}" in
--short) mode=(--short) ;;
"") ;;
*)
    echo "usage: $0 [--short]" >&2
    exit 2
    ;;
esac
failed=()
for script in validation/*/run.py; do
    name=$(basename "$(dirname "$script")")
    t0=$SECONDS
    if "$py" "$script" "${mode[@]}"; then
        echo "== validation $name: ok ($((SECONDS - t0)) s)"
    else
        echo "== validation $name: FAILED ($((SECONDS - t0)) s)"
        failed+=("$name")
    fi
done
if [ ${#mode[@]} -eq 0 ]; then
    "$py" validation/gallery.py || failed+=("gallery page")
fi
if [ ${#failed[@]} -gt 0 ]; then
    echo "validation FAILED: ${failed[*]}"
    exit 1
fi
