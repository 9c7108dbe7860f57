"""cmake --install into a temporary prefix gives an importable module that renders with the
config installed beside it."""

import os
import pathlib
import subprocess
import sys

from conftest import BUILD, CORNELL

SCRIPT = """
import sys, kiln
image = kiln.render(kiln.load(sys.argv[1]), resolution=(24, 18), spp=2, aovs=["N"])
written = image.write(sys.argv[2])
print(kiln.__file__)
print(image.metadata["kiln:ocio_config"])
print(written["exr"], written["preview"])
"""


def test_cmake_install_into_a_temporary_prefix_gives_an_importable_module(tmp_path):
    prefix = tmp_path / "prefix with space"
    subprocess.run(["cmake", "--install", str(BUILD), "--prefix", str(prefix)], check=True,
                   capture_output=True)
    site = prefix / os.environ.get("KILN_PYTHON_INSTALL_DIR", "")
    package = site / "kiln"
    assert (package / "__init__.py").exists() and (package / "config.ocio").exists()
    assert list(package.glob("_kiln*.so"))

    env = {k: v for k, v in os.environ.items() if k not in ("OCIO", "PYTHONPATH")}
    env["PYTHONPATH"] = str(site)
    out = tmp_path / "render"
    result = subprocess.run([sys.executable, "-c", SCRIPT, str(CORNELL), str(out)], cwd="/",
                            env=env, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    module, config, files = result.stdout.splitlines()
    assert pathlib.Path(module).parent == package
    assert config == str(package / "config.ocio")
    assert files == f"{out}.exr {out}.png"
    assert pathlib.Path(f"{out}.exr").exists() and pathlib.Path(f"{out}.png").exists()
