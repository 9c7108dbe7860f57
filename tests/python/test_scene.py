"""A scene loaded once renders many times; bad input and bad options fail as kiln render fails."""

import json
import os

import numpy as np
import pytest

import kiln
from conftest import CBSPHERES, CORNELL, SHARED, layer_of, read_exr, run_kiln


def same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_one_scene_renders_twice_with_different_cameras_without_reloading(tmp_path):
    scene = kiln.load(CBSPHERES)
    loaded = scene.load_seconds
    job = kiln.RenderOptions(resolution=(48, 36), spp=2, aovs=[])
    plain = kiln.render(scene, job)
    cameras = [
        dict(turntable=8, frame=1),
        dict(position=(0.5, 1.2, 2.5), look_at=(0, 0.6, 0), fov=45),
    ]
    images = [kiln.render(scene, job, **camera) for camera in cameras]

    assert not same_bits(images[0].beauty, images[1].beauty)
    assert not same_bits(images[0].beauty, plain.beauty)
    # Built once, loaded once: one accelerator for the three renders, the same load.
    assert len(scene.accelerators) == 1 and "embree" in scene.accelerators[0]["description"].lower()
    assert scene.load_seconds == loaded
    # Each camera's override was the render's alone: the scene's own camera is back.
    assert same_bits(kiln.render(scene, job).beauty, plain.beauty)
    # And each equals kiln render with the same camera options, bit for bit.
    flags = [["--turntable", 8, "--frame", 1],
             ["--position", 0.5, 1.2, 2.5, "--look-at", 0, 0.6, 0, "--fov", 45]]
    for image, extra in zip(images, flags):
        run_kiln("render", CBSPHERES, "-r", 48, 36, "-s", 2, "--aov", "none", "-q", *extra,
                 "-o", tmp_path / "cli")
        pixels, names, _ = read_exr(tmp_path / "cli.exr")
        assert same_bits(image.beauty, layer_of(pixels, names, ""))


def test_the_reference_bvh_renders_the_same_scene_too(cbspheres):
    job = kiln.RenderOptions(resolution=(32, 24), spp=2, aovs=["N"])
    embree = kiln.render(cbspheres, job)
    reference = kiln.render(cbspheres, job, accel="reference")
    assert reference.metadata["kiln:accelerator"] != embree.metadata["kiln:accelerator"]
    # Both are exact tracers of one scene: the normals agree but at rare edge pixels.
    assert np.mean(np.all(embree.aov("N") == reference.aov("N"), axis=2)) > 0.95
    assert {a["description"] for a in cbspheres.accelerators} >= {
        embree.metadata["kiln:accelerator"], reference.metadata["kiln:accelerator"]}


def test_info_is_kiln_info_json(cbspheres):
    cli = json.loads(run_kiln("info", CBSPHERES, "--json").stdout)
    info = cbspheres.info()
    for d in (cli, info):
        d.pop("load_seconds", None)
    assert info == cli


def test_crosscheck_is_kiln_crosscheck_json(cbspheres):
    cli = json.loads(run_kiln("crosscheck", CBSPHERES, "--json", "--rays", 4000).stdout)
    report = kiln.crosscheck(cbspheres, rays=4000)
    assert report == cli
    assert set(report) >= {"scene", "categories"}


def test_an_environment_map_by_keyword_renders_as_dash_e(tmp_path):
    env = SHARED / "envmaps/studio.exr"
    scene = kiln.load(CORNELL, env=env, env_strength=0.5, env_rotate=30)
    assert scene.load_args == ["--env", str(env), "--env-strength", "0.5", "--env-rotate", "30"]
    image = kiln.render(scene, resolution=(32, 24), spp=2, aovs="none")
    run_kiln("render", CORNELL, "-e", env, "--env-strength", 0.5, "--env-rotate", 30,
             "-r", 32, 24, "-s", 2, "--aov", "none", "-q", "-o", tmp_path / "cli")
    pixels, names, _ = read_exr(tmp_path / "cli.exr")
    assert same_bits(image.beauty, layer_of(pixels, names, ""))


def cli_error(*args):
    """kiln's one-line message on stderr, without the 'kiln: error: ' or 'kiln render: ' lead."""
    result = run_kiln(*args, check=False)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    return lines[0]


BAD_SCENES = {
    "missing.dae": None,
    "broken.dae": "<COLLADA><asset></COLLADA>",
    "nan.obj": "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
    "range.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
}


@pytest.mark.parametrize("name", sorted(BAD_SCENES))
def test_a_bad_scene_raises_scene_error_with_the_cli_message(tmp_path, name):
    path = tmp_path / name
    if BAD_SCENES[name] is not None:
        path.write_text(BAD_SCENES[name])
    with pytest.raises(kiln.SceneError) as error:
        kiln.load(path)
    message = str(error.value)
    assert str(path) in message and "\n" not in message
    assert cli_error("render", path, "-r", 8, 6, "-q", "-o", tmp_path / "out").endswith(": " + message)


def test_a_missing_environment_map_is_a_scene_error(tmp_path):
    with pytest.raises(kiln.SceneError, match="nowhere.exr"):
        kiln.load(CORNELL, env=tmp_path / "nowhere.exr")


@pytest.mark.parametrize("keywords, flags", [
    (dict(spp=0), ["-s", "0"]),
    (dict(resolution=(0, 10)), ["-r", "0", "10"]),
    (dict(aovs=["direct", "bogus"]), ["--aov", "direct,bogus"]),
    (dict(sampling="sideways"), ["--sampling", "sideways"]),
    (dict(rr_continue=1.5), ["--rr-continue", "1.5"]),
    (dict(fov=200), ["--fov", "200"]),
    (dict(adaptive=(16, 0.05), noise_threshold=0.01), ["-a", "16", "0.05", "--noise-threshold", "0.01"]),
    (dict(view="No Such View"), ["--view", "No Such View"]),
])
def test_a_bad_option_raises_value_error_with_the_cli_message(tmp_path, keywords, flags):
    with pytest.raises(ValueError) as error:
        kiln.RenderOptions(**keywords)
    cli = cli_error("render", CORNELL, *flags, "-q", "-o", tmp_path / "out")
    assert cli == "kiln render: " + str(error.value)


def test_options_that_are_not_the_renders_or_are_not_built_say_so(cbspheres):
    with pytest.raises(TypeError, match="did you mean spp"):
        kiln.RenderOptions(sppp=4)
    with pytest.raises(TypeError, match="unexpected keyword argument 'output'"):
        kiln.RenderOptions(output="x")
    with pytest.raises(TypeError, match="takes 2 values"):
        kiln.RenderOptions(resolution=640)
    with pytest.raises(TypeError, match="takes True or False"):
        kiln.RenderOptions(half="yes")
    # A camera the scene cannot take fails at the render, as kiln render fails after loading.
    with pytest.raises(ValueError, match="--turntable and --frame go together"):
        kiln.render(cbspheres, resolution=(8, 6), frame=2)
