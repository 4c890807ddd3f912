"""Fixtures of the fmpy tests: the built FMUs (built if absent), unzipped once per session, and
`fmi`, which runs a test once through each FMI version."""

import types
import zipfile

import pytest
from fmpy import read_model_description

from viscosph_fmu import FMU, FMU3, build_fmu


@pytest.fixture(scope="session")
def fmu():
    if not FMU.is_file():
        build_fmu()
    return str(FMU)


@pytest.fixture(scope="session")
def fmu3(fmu):
    # fmu-build writes both FMUs; the fixture `fmu` builds them if the FMI 2.0 one is absent
    if not FMU3.is_file():
        build_fmu()
    return str(FMU3)


def _unzip(fmu, tmp_path_factory, name):
    d = tmp_path_factory.mktemp(name)
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    return d


@pytest.fixture(scope="session")
def unzipdir(fmu, tmp_path_factory):
    """The FMU extracted once: instances created from it share one loaded library, as several
    instances in one process do."""
    return str(_unzip(fmu, tmp_path_factory, "ViscoSPH"))


@pytest.fixture(scope="session")
def unzip3(fmu3, tmp_path_factory):
    return _unzip(fmu3, tmp_path_factory, "ViscoSPH-fmi3")


@pytest.fixture(scope="session")
def md(fmu):
    return read_model_description(fmu)


@pytest.fixture(params=["fmi2", "fmi3"])
def fmi(request):
    """One FMI version's FMU: `api` ("fmi2" / "fmi3", the prefix of its function names), `fmu`
    (the archive), `unzipdir` and `md`. Drive it with viscosph_fmu.Slave(fmi.unzipdir), which
    makes each call the way that version makes it."""
    if request.param == "fmi2":
        fmu, unzipdir = request.getfixturevalue("fmu"), request.getfixturevalue("unzipdir")
    else:
        fmu, unzipdir = request.getfixturevalue("fmu3"), str(request.getfixturevalue("unzip3"))
    return types.SimpleNamespace(api=request.param, fmu=fmu, unzipdir=unzipdir,
                                 md=read_model_description(fmu))
