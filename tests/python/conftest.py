"""Shared set-up of the kiln module's tests (run by ctest as python.test_*; by hand:
`/usr/bin/python3 -m pytest tests/python` after a build in build/).

The module is the build tree's (build/python), the kiln binary beside it renders the references.
A run that collects nothing (pytest's exit 5) or skips a test fails: these tests must really run.
"""

import os
import pathlib
import shlex
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(os.environ.get("KILN_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BUILD = pathlib.Path(os.environ.get("KILN_BUILD_DIR", SOURCE / "build"))
SHARED = pathlib.Path(os.environ.get("KILN_SHARED_DIR", SOURCE.parent / "shared"))
BINARY = pathlib.Path(os.environ.get("KILN_BINARY", BUILD / "kiln"))

sys.path.insert(0, str(BUILD / "python"))
import kiln  # noqa: E402  (the build tree's module, whatever else is installed)

assert pathlib.Path(kiln.__file__).resolve().is_relative_to((BUILD / "python").resolve()), kiln.__file__

CBSPHERES = SHARED / "scenes/cs184/sky/CBspheres_lambertian.dae"
CORNELL = SOURCE / "scenes/cornell.dae"


def pytest_sessionfinish(session, exitstatus):
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    skipped = reporter.stats.get("skipped", []) if reporter else []
    if skipped or session.testscollected == 0:
        session.exitstatus = 1


def run_kiln(*args, check=True):
    """Runs the kiln binary; returns the CompletedProcess (text)."""
    result = subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"kiln {shlex.join(map(str, args))} exited {result.returncode}: {result.stderr}")
    return result


def read_exr(path):
    """Every channel of an EXR as float32 (H, W, C), its channel names and its header."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    pixels = inp.read_image(0, spec.nchannels, "float")
    header = {a.name: spec.getattribute(a.name) for a in spec.extra_attribs}
    names = list(spec.channelnames)
    inp.close()
    return pixels, names, header


def layer_of(pixels, names, layer):
    """The channels of one layer ("" for R, G, B, A) in the file's order."""
    if layer == "":
        idx = [names.index(c) for c in "RGBA"]
    elif layer == "Z":
        idx = [names.index("Z")]
    else:
        idx = [i for i, n in enumerate(names) if n.rsplit(".", 1)[0] == layer and "." in n]
    return pixels[:, :, idx]


@pytest.fixture(scope="session")
def cbspheres():
    assert CBSPHERES.exists(), f"missing shared data: {CBSPHERES}"
    return kiln.load(str(CBSPHERES))
