"""Arrays view kiln's buffers: filled once, never copied per access, alive as long as a view is."""

import gc

import numpy as np

import kiln


def resident_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise AssertionError("no VmRSS")


def test_layers_are_filled_once_and_viewed(cbspheres):
    image = kiln.render(cbspheres, resolution=(64, 48), spp=1, aovs=["all"])
    beauty = image.beauty
    assert not beauty.flags.writeable and beauty.base is not None
    assert np.shares_memory(beauty, image.beauty)
    for name in image.aovs:
        assert np.shares_memory(image.aov(name), image.aov(name)), name
    counts = image.samples
    assert counts.dtype == np.uint32 and counts.shape == (48, 64)
    assert np.shares_memory(counts, image.samples)  # the film's own counts, not a copy
    # A view keeps its image alive.
    direct = image.aov("direct")
    kept = direct.copy()
    del image, beauty, counts
    gc.collect()
    assert np.array_equal(direct, kept)


def test_an_aov_all_render_does_not_double_its_memory_through_python(cbspheres):
    image = kiln.render(cbspheres, resolution=(512, 384), spp=1, aovs=["all"])
    before = resident_bytes()
    arrays = [image.beauty] + [image.aov(name) for name in image.aovs]
    floats = sum(a.nbytes for a in arrays)
    filled = resident_bytes()
    # One float per channel per pixel, once (the size of the EXR's float data).
    assert filled - before <= floats * 1.1 + (8 << 20)
    again = [image.beauty] + [image.aov(name) for name in image.aovs]
    assert resident_bytes() - filled <= 4 << 20
    assert all(np.shares_memory(a, b) for a, b in zip(arrays, again))
