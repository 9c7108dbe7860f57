"""The module renders what kiln render renders: the same pixels, bit for bit, the same header."""

import numpy as np
import OpenImageIO as oiio

import kiln
from conftest import CBSPHERES, layer_of, read_exr, run_kiln

AOVS = ["direct", "indirect", "albedo", "N", "Z", "samples", "variance"]
CLI_ARGS = ["-r", 64, 48, "-s", 4, "-m", 5, "--seed", 3, "--aov", ",".join(AOVS), "-q"]
# What two renders of the same options may differ in: times, and the outputs' names.
VARYING = {"kiln:render_seconds", "DateTime"}  # a second may pass between the two renders


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_beauty_and_aovs_are_bit_identical_to_kiln_render(tmp_path, cbspheres):
    run_kiln("render", CBSPHERES, *CLI_ARGS, "-o", tmp_path / "cli")
    pixels, names, header = read_exr(tmp_path / "cli.exr")

    job = kiln.RenderOptions(resolution=(64, 48), spp=4, max_depth=5, seed=3, threads=0, aovs=AOVS, denoise=False)
    image = kiln.render(cbspheres, job)

    assert image.beauty.dtype == np.float32 and image.beauty.shape == (48, 64, 4)
    assert same_bits(image.beauty, layer_of(pixels, names, ""))
    assert image.aovs == AOVS
    for aov in AOVS:
        assert same_bits(image.aov(aov), layer_of(pixels, names, aov)), aov
    assert image.aov("direct").shape == (48, 64, 3) and image.aov("Z").shape == (48, 64, 1)
    assert np.array_equal(image.samples, np.full((48, 64), 4, np.uint32))
    assert not image.interrupted

    # The header: every attribute the module names is in the CLI's EXR, with the same value.
    assert image.metadata["kiln:scene"] == str(CBSPHERES)
    for key, value in image.metadata.items():
        if key not in VARYING:
            assert header[key] == value, key
    assert not {k for k in header if k.startswith("kiln:")} - set(image.metadata)


def test_write_gives_the_files_of_kiln_render(tmp_path, cbspheres):
    run_kiln("render", CBSPHERES, *CLI_ARGS, "-o", tmp_path / "cli")
    image = kiln.render(cbspheres, resolution=(64, 48), spp=4, max_depth=5, seed=3, aovs=",".join(AOVS))
    written = image.write(tmp_path / "py")
    assert written == {"exr": str(tmp_path / "py.exr"), "preview": str(tmp_path / "py.png")}

    cli, cli_names, cli_header = read_exr(tmp_path / "cli.exr")
    py, py_names, py_header = read_exr(tmp_path / "py.exr")
    assert py_names == cli_names
    assert same_bits(py, cli)
    for key, value in image.metadata.items():
        assert py_header[key] == value, key
    assert {k: v for k, v in py_header.items() if k not in VARYING} == {
        k: v for k, v in cli_header.items() if k not in VARYING
    }
    png = [oiio.ImageInput.open(str(tmp_path / f"{n}.png")) for n in ("cli", "py")]
    assert np.array_equal(png[0].read_image(0, 3, "uint8"), png[1].read_image(0, 3, "uint8"))


def test_every_option_by_name_gives_the_command_lines_arguments():
    job = kiln.RenderOptions(
        resolution=(640, 480), spp=64, max_depth=5, seed=0, threads=0, aovs=["direct", "N"],
        sampling="bsdf", rr_continue=0.5, look_at=(0, 1, 0), hemisphere=True, half=False,
    )
    assert job.args == [
        "--resolution", "640", "480", "--spp", "64", "--max-depth", "5", "--seed", "0",
        "--aov", "direct,N", "--sampling", "bsdf", "--rr-continue", "0.5",
        "--look-at", "0", "1", "0", "--hemisphere",
    ]
    assert job.replace(spp=None).args[:3] == ["--resolution", "640", "480"]
    assert "--spp" not in job.replace(spp=None).args
    names = kiln.RenderOptions.names()
    for name in ["resolution", "crop", "spp", "threads", "tile", "sampler", "seed", "adaptive",
                 "noise_threshold", "integrator", "max_depth", "light_samples", "hemisphere",
                 "sampling", "heuristic", "rr", "guiding", "plan", "aov", "display", "view",
                 "exposure", "half", "heatmap", "compression", "transparent", "depth", "aperture",
                 "focus", "position", "look_at", "up", "fov", "turntable", "frame", "orbit_axis",
                 "orbit_centre", "accel", "embree_quality", "watertight", "bvh_leaf"]:
        assert name in names, name
    for not_here in ["output", "file", "checkpoint_every", "resume", "pixel", "json", "env", "camera"]:
        assert not_here not in names


def test_a_render_options_set_renders_any_scene_again(tmp_path, cbspheres):
    job = kiln.RenderOptions(resolution=(32, 24), spp=2, aovs=[])
    a = kiln.render(cbspheres, job)
    b = kiln.render(cbspheres, job)
    assert same_bits(a.beauty, b.beauty)
    assert a.aovs == []


def test_denoise_gives_the_denoised_beauty_and_keeps_the_noisy_one_as_kiln_render_does(tmp_path, cbspheres):
    args = ["-r", 64, 48, "-s", 4, "-m", 5, "--seed", 3, "--denoise", "--denoise-aovs", "direct", "-q"]
    run_kiln("render", CBSPHERES, *args, "--aov", "direct", "-o", tmp_path / "cli")
    pixels, names, header = read_exr(tmp_path / "cli.exr")

    image = kiln.render(cbspheres, resolution=(64, 48), spp=4, max_depth=5, seed=3, aovs="direct",
                        denoise=True, denoise_aovs="direct")
    assert same_bits(image.beauty, layer_of(pixels, names, ""))
    assert same_bits(image.aov("noisy"), layer_of(pixels, names, "noisy")[:, :, :3])
    assert same_bits(image.aov("direct"), layer_of(pixels, names, "direct"))
    assert same_bits(image.aov("noisy.direct"), layer_of(pixels, names, "noisy.direct"))
    assert not np.array_equal(image.beauty[:, :, :3], image.aov("noisy"))
    # Denoised once for reading and writing: each write carries that one denoising's time, and
    # its pixels.
    image.write(tmp_path / "a")
    image.write(tmp_path / "b")
    a_pixels, a_names, a_header = read_exr(tmp_path / "a.exr")
    b_header = read_exr(tmp_path / "b.exr")[2]
    assert a_header["kiln:denoise_seconds"] == b_header["kiln:denoise_seconds"]
    assert same_bits(layer_of(a_pixels, a_names, ""), image.beauty)
