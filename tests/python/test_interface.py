"""The FMU as a file: its model description validates, fmpy shows every contract variable, and
the worked example of its documentation runs."""

import re
import subprocess
import sys
import zipfile

import fmpy
from fmpy.validation import validate_fmu

from viscosph_fmu import CONTRACT_OUTPUTS, CONTRACT_PARAMETERS


def test_validate_fmu_reports_no_problems(fmu):
    assert validate_fmu(fmu) == []


def test_no_output_depends_directly_on_an_input(fmi):
    # ModelStructure/Outputs with dependencies="" in FMI 2.0 and 3.0: a master that reads it
    # (OMSimulator) finds no algebraic loop in a two-way coupling. fmpy reads "" as an empty list.
    md = fmi.md
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert [u.variable for u in md.outputs] == outputs
    assert all(u.dependencies == [] for u in md.outputs)
    # InitialUnknowns: every output (initial = "calculated"), depending on all knowns.
    assert [u.variable for u in md.initialUnknowns] == outputs


def test_archive_holds_description_binary_and_documentation(fmu):
    names = set(zipfile.ZipFile(fmu).namelist())
    assert {"modelDescription.xml", "binaries/linux64/ViscoSPH.so",
            "documentation/index.html"} <= names


def test_dump_shows_every_contract_variable(fmu, capsys):
    fmpy.dump(fmu, causalities=["parameter", "output"])
    text = capsys.readouterr().out
    assert "ViscoSPH" in text and "Co-Simulation" in text
    for name in CONTRACT_PARAMETERS + CONTRACT_OUTPUTS:
        # fmpy abbreviates names longer than 18 characters to "..." + their last 15
        shown = name if len(name) <= 18 else "..." + name[-15:]
        assert re.search(rf"^\s*{re.escape(shown)}\s", text, re.M), name


def test_contract_variables_have_the_right_causality_units_and_defaults(md):
    by_name = {v.name: v for v in md.modelVariables}
    for name in CONTRACT_PARAMETERS:
        assert by_name[name].causality == "parameter"
        assert by_name[name].variability == "fixed"
    for name in CONTRACT_OUTPUTS:
        assert by_name[name].causality == "output"
        assert by_name[name].variability == "continuous"
    units = {"plate_inclination": "deg", "impact_velocity": "m/s", "drop_diameter": "m",
             "initial_drop_height": "m", "density": "kg/m3", "gravity": "m/s2",
             "viscosity": "Pa.s", "relaxation_time": "s", "drop_width": "m",
             "wall_force_normal": "N/m", "kinetic_energy": "J/m", "time_step": "s"}
    for name, unit in units.items():
        assert by_name[name].unit == unit, name
    assert {u.name for u in md.unitDefinitions} >= {
        "m", "m/s", "deg", "kg/m3", "m/s2", "Pa.s", "s", "N/m", "J/m"}
    # Fang 2006's Oldroyd-B drop is the default.
    defaults = {"drop_diameter": "0.02", "impact_velocity": "1", "viscosity": "4",
                "viscosity_ratio": "0.1", "relaxation_time": "0.02"}
    for name, start in defaults.items():
        assert float(by_name[name].start) == float(start), name
    rheology = by_name["rheology"]
    items = {i.name: int(i.value) for i in rheology.declaredType.items}
    assert int(rheology.start) == items["oldroyd_b"]
    for t in ["Scene", "Scheme", "Rheology"]:
        assert t in {d.name for d in md.typeDefinitions}
    assert md.defaultExperiment.stopTime == "0.16"
    cs = md.coSimulation
    assert cs.canHandleVariableCommunicationStepSize and cs.canGetAndSetFMUstate
    assert cs.canSerializeFMUstate and cs.canNotUseMemoryManagementFunctions
    assert not cs.canBeInstantiatedOnlyOncePerProcess
    assert md.modelExchange is None


def test_documentation_example_runs(fmu, tmp_path):
    html = zipfile.ZipFile(fmu).read("documentation/index.html").decode()
    for name in CONTRACT_PARAMETERS + CONTRACT_OUTPUTS:
        assert f"<code>{name}</code>" in html, name
    example = re.search(r"<pre>(.*?)</pre>", html, re.S).group(1)
    example = (example.replace("&quot;", '"').replace("&apos;", "'").replace("&lt;", "<")
               .replace("&gt;", ">").replace("&amp;", "&"))
    example = example.replace('fmu = "ViscoSPH.fmu"', f'fmu = {fmu!r}')
    script = tmp_path / "example.py"
    script.write_text("import matplotlib\nmatplotlib.use('Agg')\n" + example)
    run = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "drop.png").stat().st_size > 0
    # the refused value is explained by the FMU's own log message
    assert "plate_inclination" in run.stdout and "[0, 90)" in run.stdout, run.stdout
