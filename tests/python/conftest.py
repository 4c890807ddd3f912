"""Fixtures of the fmpy tests: the built FMU (built if absent), unzipped once per session."""

import zipfile

import pytest
from fmpy import read_model_description

from viscosph_fmu import FMU, build_fmu


@pytest.fixture(scope="session")
def fmu():
    if not FMU.is_file():
        build_fmu()
    return str(FMU)


@pytest.fixture(scope="session")
def unzipdir(fmu, tmp_path_factory):
    """The FMU extracted once: instances created from it share one loaded library, as several
    instances in one process do."""
    d = tmp_path_factory.mktemp("ViscoSPH")
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    return str(d)


@pytest.fixture(scope="session")
def md(fmu):
    return read_model_description(fmu)
