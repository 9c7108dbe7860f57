"""docs/python.md's walkthrough runs against the module as built: every python block of the page,
in order, in one namespace, at a small size (resolution, samples and rays capped)."""

import os
import re

import kiln
from conftest import SOURCE

SMALL = dict(resolution=(40, 30), spp=2)


def small(keywords):
    keywords = dict(keywords)
    for key, value in SMALL.items():
        if key in keywords:
            keywords[key] = value
    return keywords


def test_the_walkthrough_runs(tmp_path, monkeypatch):
    text = (SOURCE / "docs/python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) >= 6

    load, render, crosscheck, options = kiln.load, kiln.render, kiln.crosscheck, kiln.RenderOptions
    loaded = []

    def load_here(path, **kw):  # the page's paths are relative to the repository root
        if path.startswith("no/such"):
            return load(path, **kw)
        loaded.append(path)
        return load(os.path.join(SOURCE, path), **kw)

    monkeypatch.setattr(kiln, "load", load_here)
    monkeypatch.setattr(kiln, "RenderOptions", lambda **kw: options(**small(kw)))
    monkeypatch.setattr(kiln, "render", lambda scene, job=None, **kw: render(scene, job, **small(kw)))
    monkeypatch.setattr(kiln, "crosscheck", lambda scene, rays=1000000, **kw: crosscheck(scene, rays=min(rays, 4000), **kw))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    import matplotlib

    matplotlib.use("Agg")
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)

    assert loaded == ["../shared/scenes/cs184/sky/CBspheres_lambertian.dae"]
    assert (tmp_path / "spheres.exr").exists() and (tmp_path / "spheres.png").exists()
    assert len(list((tmp_path / "turntable").glob("spheres.*.exr"))) == 24
    assert len(namespace["scene"].accelerators) == 2  # Embree and the reference BVH, once each
    assert namespace["first"].interrupted
