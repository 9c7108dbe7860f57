"""Renders run with the GIL released and stop when asked: a callback returning False, an event
set from another thread, Ctrl-C. They stop within the tile in hand and keep the samples so far."""

import _thread
import threading
import time

import numpy as np
import pytest

import kiln

TILE = 16


def test_a_callback_returning_false_stops_within_one_tile(cbspheres):
    calls = []

    def progress(done, total):
        calls.append((done, total))
        return False

    image = kiln.render(cbspheres, resolution=(96, 64), spp=8, threads=1, tile=TILE, aovs=[],
                        progress=progress)
    assert calls == [(TILE * TILE, 96 * 64 * 8)]  # the first tile of the first wave (1 sample)
    assert image.interrupted and image.metadata["kiln:interrupted"] == "yes"
    samples = image.samples
    assert samples.sum() == TILE * TILE  # that tile's samples, nothing after it
    assert np.all(samples[:TILE, :TILE] == 1)
    # The samples so far are the image so far: nothing outside that tile.
    assert np.all(image.beauty[TILE:] == 0) and np.all(image.beauty[:, TILE:] == 0)


def test_with_several_threads_a_cancel_stops_within_a_tile_per_thread(cbspheres):
    threads = 2
    first = []
    image = kiln.render(cbspheres, resolution=(128, 96), spp=16, threads=threads, tile=TILE,
                        aovs=[], progress=lambda done, total: first.append(done) or False)
    assert len(first) == 1 and image.interrupted
    # The tiles done when the callback answered, and at most one more tile per other thread.
    assert first[0] <= image.samples.sum() <= first[0] + (threads - 1) * TILE * TILE


def test_progress_counts_every_sample_and_the_render_completes(cbspheres):
    calls = []
    image = kiln.render(cbspheres, resolution=(64, 48), spp=4, threads=1, tile=TILE, aovs=[],
                        progress=lambda done, total: calls.append((done, total)))
    assert not image.interrupted and np.all(image.samples == 4)
    assert calls[-1] == (64 * 48 * 4, 64 * 48 * 4)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    assert len(calls) == 4 * 3 * 3  # each of the 12 tiles in each wave (samples 0, 1, 2-3)


def test_an_event_set_from_another_thread_cancels_a_render(cbspheres):
    cancel = threading.Event()
    result = {}

    def work():
        result["image"] = kiln.render(cbspheres, resolution=(320, 240), spp=512, aovs=[],
                                      cancel=cancel)

    thread = threading.Thread(target=work)
    start = time.monotonic()
    thread.start()
    time.sleep(0.5)
    cancel.set()
    thread.join(timeout=30)
    assert not thread.is_alive()
    assert time.monotonic() - start < 10
    image = result["image"]
    assert image.interrupted and 0 < image.samples.sum() < 320 * 240 * 512


def test_the_gil_is_released_while_rendering(cbspheres):
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    try:
        kiln.render(cbspheres, resolution=(160, 120), spp=16, aovs=[])
    finally:
        stop.set()
        thread.join()
    assert len(ticks) > 20


def test_ctrl_c_stops_the_render_and_raises_keyboard_interrupt_with_the_image(cbspheres):
    # Ctrl-C as Python sees it, from another thread once the render runs, while this thread
    # waits in kiln.render.
    timer = threading.Timer(0.2, _thread.interrupt_main)

    def progress(done, total):
        if not timer.is_alive() and not timer.finished.is_set():
            timer.start()

    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as error:
        kiln.render(cbspheres, resolution=(320, 240), spp=512, aovs=[], progress=progress)
    timer.join()
    assert time.monotonic() - start < 10
    image = error.value.image
    assert image.interrupted and 0 < image.samples.sum() < 320 * 240 * 512


def test_an_exception_in_the_callback_stops_the_render_and_propagates(cbspheres):
    def progress(done, total):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough") as error:
        kiln.render(cbspheres, resolution=(64, 48), spp=64, threads=1, tile=TILE, aovs=[],
                    progress=progress)
    assert error.value.image.samples.sum() == TILE * TILE


def test_the_scene_answers_from_a_callback_and_renders_take_turns_across_threads(cbspheres):
    seen = []

    def progress(done, total):
        seen.append((cbspheres.info()["triangles"], len(cbspheres.accelerators)))
        with pytest.raises(RuntimeError, match="rendering the scene already"):
            kiln.render(cbspheres, resolution=(8, 6))

    images = [None, None]

    def work(i):
        images[i] = kiln.render(cbspheres, resolution=(48, 36), spp=2, aovs=[], tile=TILE,
                                progress=progress, turntable=4, frame=i)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert not any(t.is_alive() for t in threads)
    assert seen and all(triangles == 12 for triangles, _ in seen)
    assert all(image is not None and not image.interrupted for image in images)
    alone = kiln.render(cbspheres, resolution=(48, 36), spp=2, aovs=[], turntable=4, frame=1)
    assert np.array_equal(images[1].beauty, alone.beauty)
