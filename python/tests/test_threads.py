"""A Renderer belongs to the thread that made it; other threads get a clean RenderError, and
several Renderers on one thread each draw in their own context."""

import threading

import numpy as np
import pytest

import omnishadow


def run_in_thread(function):
    result = {}

    def target():
        try:
            result["value"] = function()
        except BaseException as error:  # handed back to the test's thread
            result["error"] = error

    thread = threading.Thread(target=target)
    thread.start()
    thread.join(timeout=120)
    assert not thread.is_alive()
    return result


def test_render_from_another_thread_fails_cleanly(renderer, demo_scene):
    before = renderer.render(demo_scene, width=16, height=16)
    result = run_in_thread(lambda: renderer.render(demo_scene, width=16, height=16))
    error = result.get("error")
    assert isinstance(error, omnishadow.RenderError), result
    assert "another thread" in str(error) and "one Renderer per thread" in str(error)
    # The owner thread still renders, and the same frame as before.
    after = renderer.render(demo_scene, width=16, height=16)
    np.testing.assert_array_equal(before.beauty, after.beauty)


def test_each_thread_may_own_a_renderer(demo_scene):
    def own():
        return omnishadow.Renderer().render(demo_scene, width=16, height=16).beauty

    result = run_in_thread(own)
    assert "error" not in result, result
    assert result["value"].shape == (16, 16, 4)


def test_gil_is_released_while_rendering(renderer, demo_scene):
    # A Python thread keeps counting while the main thread renders; were the GIL held for the
    # whole render, it could not count at all.
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    counter = threading.Thread(target=spin)
    counter.start()
    before = count[0]
    renderer.render(demo_scene, width=256, height=256, aovs=["all"], aa=4)
    during = count[0] - before
    stop.set()
    counter.join()
    assert during > 100


def test_a_new_renderer_on_the_same_thread_leaves_the_old_one_whole(renderer, demo_scene):
    # As in a notebook cell run twice: `r = Renderer()` makes the new one before the old goes.
    expected = renderer.render(demo_scene, width=16, height=16).beauty
    r = omnishadow.Renderer()
    r = omnishadow.Renderer()  # the first of the two ends here, after the second was made
    np.testing.assert_array_equal(r.render(demo_scene, width=16, height=16).beauty, expected)
    np.testing.assert_array_equal(renderer.render(demo_scene, width=16, height=16).beauty,
                                  expected)
    del r
    np.testing.assert_array_equal(renderer.render(demo_scene, width=16, height=16).beauty,
                                  expected)
