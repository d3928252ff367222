"""Queries release the GIL: Python threads trace one scene at once, and refit() may run
between their queries, and every thread gets the single-threaded answer."""

import threading

import numpy as np

import reference as ref
import sphray


def run_in_threads(work, count):
    errors, threads = [], []

    def guarded(i):
        try:
            work(i)
        except BaseException as e:  # reported below, in the test's thread
            errors.append(e)

    for i in range(count):
        threads.append(threading.Thread(target=guarded, args=(i,)))
        threads[-1].start()
    for th in threads:
        th.join(timeout=120)
        assert not th.is_alive(), "a tracing thread did not finish"
    assert not errors, errors


def test_two_threads_trace_at_once_and_agree(rng):
    centers, radii = ref.random_scene(rng, 4096, box=30)
    origins, directions = ref.random_rays(rng, 50000, box=32)
    scene = sphray.Scene(centers, radii)
    expected = scene.intersect(origins, directions)
    results = [None, None]

    def work(i):
        for _ in range(3):
            results[i] = scene.intersect(origins, directions)

    run_in_threads(work, 2)
    for t, ids in results:
        np.testing.assert_array_equal(ids, expected[1])
        np.testing.assert_array_equal(t, expected[0])


def test_refit_between_queries_of_other_threads(rng):
    centers, radii = ref.random_scene(rng, 2000, box=20)
    origins, directions = ref.random_rays(rng, 20000, box=22)
    scene = sphray.Scene(centers, radii)
    expected = scene.intersect(origins, directions)

    def work(i):
        for _ in range(5):
            if i == 0:
                scene.refit(centers.copy(), radii.copy())   # the same spheres, new arrays
            else:
                t, ids = scene.intersect(origins, directions)
                np.testing.assert_array_equal(ids, expected[1])

    run_in_threads(work, 3)
