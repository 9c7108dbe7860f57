"""Input the module must refuse with a clear error, or honour as the command line does: paths
with a NUL or not in UTF-8, numpy's booleans, huge integers, callbacks of the wrong kind, a film
larger than memory; and two threads making their first numpy views at once."""

import os
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import kiln
from conftest import BUILD, CBSPHERES


def test_a_nul_in_a_path_or_a_value_is_refused_naming_the_argument(cbspheres, tmp_path):
    with pytest.raises(ValueError, match="path: embedded null character"):
        kiln.load(str(CBSPHERES) + "\0.obj")
    with pytest.raises(ValueError, match="env: embedded null character"):
        kiln.load(CBSPHERES, env="map.exr\0zzz")
    image = kiln.render(cbspheres, resolution=(16, 12), spp=1)
    with pytest.raises(ValueError, match="out: embedded null character"):
        image.write(str(tmp_path / "out\0ignored"))
    assert os.listdir(tmp_path) == []


def test_a_path_that_is_not_utf8_loads_and_writes_as_on_the_command_line(tmp_path):
    folder = os.fsencode(tmp_path) + b"/shot\xff"
    os.mkdir(folder)
    shutil.copy(CBSPHERES, folder + b"/scene.dae")
    scene = kiln.load(folder + b"/scene.dae")
    assert os.fsencode(scene.path) == folder + b"/scene.dae"
    assert kiln.load(os.fsdecode(folder + b"/scene.dae")).path == scene.path
    written = kiln.render(scene, resolution=(16, 12), spp=1).write(os.fsdecode(folder + b"/out"))
    assert os.fsencode(written["exr"]) == folder + b"/out.exr"
    assert sorted(os.listdir(folder)) == [b"out.exr", b"out.png", b"scene.dae"]
    with pytest.raises(kiln.SceneError, match="missing"):
        kiln.load(folder + b"/missing.dae")


def test_numpy_booleans_are_switches_and_not_values():
    assert kiln.RenderOptions(transparent=np.bool_(True)).args == ["--transparent"]
    assert kiln.RenderOptions(transparent=np.bool_(False)).args == []
    with pytest.raises(TypeError, match="spp takes a value, not True or False"):
        kiln.RenderOptions(spp=np.bool_(True))


def test_huge_integers_and_keys_that_are_not_names_get_kilns_errors(cbspheres):
    with pytest.raises(ValueError, match="--threads"):
        kiln.RenderOptions(threads=2**70)
    with pytest.raises(TypeError, match="takes options by name"):
        kiln.render(cbspheres, {1: 2})


def test_callbacks_are_checked_before_the_render_and_any_false_answer_stops_it(cbspheres):
    with pytest.raises(TypeError, match="cancel takes a threading.Event"):
        kiln.render(cbspheres, resolution=(16, 12), spp=1, cancel=True)
    with pytest.raises(TypeError, match="progress takes a callable"):
        kiln.render(cbspheres, resolution=(16, 12), spp=1, progress=5)
    calls = []

    def numpy_false(done, total):
        calls.append(done)
        return np.False_

    image = kiln.render(cbspheres, resolution=(64, 48), spp=16, threads=1, progress=numpy_false)
    assert image.interrupted and len(calls) == 1


def test_a_film_larger_than_memory_is_refused_before_the_render(cbspheres, monkeypatch):
    monkeypatch.setenv("KILN_MEMORY_LIMIT", "2000000")
    with pytest.raises(ValueError, match=r"the film and the EXR write need \d+ MiB"):
        kiln.render(cbspheres, resolution=(640, 480), spp=1)


def test_the_aov_list_names_every_layer_the_image_serves(cbspheres):
    image = kiln.render(
        cbspheres, resolution=(16, 12), spp=4, denoise=True, denoise_aovs="direct", aovs=["direct", "indirect"]
    )
    assert {"noisy", "noisy.direct"} <= set(image.aovs)
    assert set(image.channels) == {""} | set(image.aovs)
    for name in image.aovs:
        assert image.aov(name).shape[:2] == (12, 16)


# numpy is not imported before the views: pybind11 set up its numpy API on first use, in a static
# whose initialisation imported numpy and gave up the GIL, and two threads deadlocked there.
def test_two_threads_making_the_first_numpy_views_at_once_do_not_deadlock():
    script = textwrap.dedent(
        f"""
        import faulthandler, sys, threading
        sys.path.insert(0, {str(BUILD / "python")!r})
        import kiln
        faulthandler.dump_traceback_later(60, exit=True)
        scene = kiln.load({str(CBSPHERES)!r})
        images = [kiln.render(scene, resolution=(16, 12), spp=1) for _ in range(2)]
        go = threading.Barrier(2)
        def first_view(image):
            go.wait()
            image.samples
        threads = [threading.Thread(target=first_view, args=(i,)) for i in images]
        [t.start() for t in threads]
        [t.join() for t in threads]
        print("views made")
        """
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and "views made" in result.stdout, result.stderr
