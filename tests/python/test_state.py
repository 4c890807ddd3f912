"""FMU states (FMI 2.0 section 2.1.8): get/set, and serialize/deserialize within the process and
into another process."""

import ctypes
import json
import subprocess
import sys

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from viscosph_fmu import ERROR, LAST_SUCCESSFUL_TIME, ROOT, Slave

T1, T2, H = 0.03, 0.05, 2e-3
SETUP = dict(reals={"plate_inclination": 15.0}, integers={"particles_per_diameter": 14})


def test_get_and_set_state_repeats_the_run_exactly(unzipdir):
    s = Slave(unzipdir).initialize(**SETUP)
    s.step_to(T1, H)
    state = s.fmu.getFMUstate()
    first = s.step_to(T2, H)
    s.fmu.setFMUstate(state)
    s.t = T1
    assert s.fmu.getRealStatus(LAST_SUCCESSFUL_TIME) == T1
    again = s.step_to(T2, H)
    assert np.array_equal(first, again)
    # overwriting a state in place (fmi2GetFMUstate with *FMUstate != NULL) then freeing it
    s.fmu.fmi2GetFMUstate(s.fmu.component, ctypes.byref(state))
    s.fmu.freeFMUstate(state)
    s.free()


def test_serialized_state_restores_in_another_instance_and_another_process(unzipdir, tmp_path):
    s = Slave(unzipdir).initialize(**SETUP)
    s.step_to(T1, H)
    state = s.fmu.getFMUstate()
    data = s.fmu.serializeFMUstate(state)
    s.fmu.freeFMUstate(state)
    reference = s.step_to(T2, H)
    s.free()

    # another instance in this process, restored from the bytes only
    other = Slave(unzipdir)
    restored = other.fmu.deSerializeFMUstate(data)
    other.fmu.setFMUstate(restored)
    other.fmu.freeFMUstate(restored)
    other.t = T1
    assert np.array_equal(other.step_to(T2, H), reference)
    other.free()

    # another process: no pointer in the bytes may matter
    (tmp_path / "state.bin").write_bytes(data)
    script = f"""
import json, sys
sys.path.insert(0, {str(ROOT / 'tests' / 'python')!r})
from viscosph_fmu import Slave
s = Slave({unzipdir!r})
st = s.fmu.deSerializeFMUstate(open({str(tmp_path / 'state.bin')!r}, 'rb').read())
s.fmu.setFMUstate(st)
s.t = {T1!r}
print(json.dumps(s.step_to({T2!r}, {H!r}).tolist()))
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    assert np.array_equal(np.array(json.loads(run.stdout)), reference)


def test_corrupt_serialized_state_is_refused(unzipdir):
    s = Slave(unzipdir).initialize(**SETUP)
    state = s.fmu.getFMUstate()
    data = s.fmu.serializeFMUstate(state)
    with pytest.raises(FMICallException) as e:
        s.fmu.deSerializeFMUstate(data[: len(data) // 2])
    assert e.value.status == ERROR
    assert any("fmi2DeSerializeFMUstate" in m for m in s.log.messages())
    s.fmu.reset()
    s.free()
