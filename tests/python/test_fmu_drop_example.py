"""examples/fmu_drop.py, the main job's script (examples/main.sh runs it under `set -e`): a
numerical breakdown still writes the CSV and the PNG but exits non-zero, and `--set` takes
enumeration items by the names the FMU's modelDescription gives them."""

import importlib.util
import subprocess
import sys

from viscosph_fmu import ROOT

SCRIPT = ROOT / "examples" / "fmu_drop.py"


def run_script(fmu, out, *sets, stop="0.1"):
    args = [sys.executable, str(SCRIPT), "--fmu", fmu, "--out", str(out), "--stop-time", stop]
    for s in sets:
        args += ["--set", s]
    return subprocess.run(args, capture_output=True, text=True, timeout=600)


def load_script():
    spec = importlib.util.spec_from_file_location("fmu_drop", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_breakdown_writes_its_files_and_exits_non_zero(fmu, tmp_path):
    # Sound far slower than the impact: the FMU discards a step shortly after impact.
    p = run_script(fmu, tmp_path, "sound_speed=1", "particles_per_diameter=12")
    assert p.returncode == 1, p.stdout + p.stderr
    assert "breakdown" in p.stderr and "error: the run ended at t =" in p.stderr, p.stderr
    rows = (tmp_path / "fmu_drop.csv").read_text().splitlines()
    t_last = float(rows[-1].split(",")[0])
    assert 2 < len(rows) and 0.0 < t_last < 0.1, (len(rows), t_last)
    assert (tmp_path / "fmu_drop.png").stat().st_size > 10_000


def test_a_full_run_exits_zero(fmu, tmp_path):
    p = run_script(fmu, tmp_path, "particles_per_diameter=8", stop="0.02")
    assert p.returncode == 0, p.stdout + p.stderr
    assert "wrote" in p.stdout


def test_enumerations_by_name_and_a_misspelt_name_is_a_clean_error(fmu, md, tmp_path):
    mod = load_script()
    items = {v.name: v for v in md.modelVariables}["rheology"].declaredType.items
    want = {i.name: int(i.value) for i in items}
    values = mod.parse_start_values(
        ["rheology=oldroyd_b", "scheme=pdri", "plate_inclination=30"], md)
    assert values["rheology"] == want["oldroyd_b"] and values["plate_inclination"] == 30.0
    assert values["scheme"] == 2  # by number, as the FMU numbers it, also accepted
    assert mod.parse_start_values(["scheme=2"], md) == {"scheme": 2}
    p = run_script(fmu, tmp_path, "rheology=oldroydb")
    assert p.returncode != 0
    assert "Traceback" not in p.stderr, p.stderr
    assert "rheology" in p.stderr and "oldroydb" in p.stderr and "oldroyd_b" in p.stderr, p.stderr
