# SPDX-License-Identifier: MIT
"""analyze releases the GIL: Python code runs while it measures, and two threads measuring at
once get the numbers one thread gets."""
import threading
import time

import numpy as np

import infocus


def frame_1080p():
    with infocus.open("sim:size=1920x1080,seed=3") as src:
        return np.array(next(src).luma)


def test_python_runs_while_analyze_measures():
    frame = frame_1080p()
    window = {}

    def measure():
        window["start"] = time.perf_counter()
        infocus.analyze(frame)
        window["end"] = time.perf_counter()

    t = threading.Thread(target=measure)
    ticks = []
    t.start()
    while t.is_alive():
        ticks.append(time.perf_counter())
    t.join()
    inside = [x for x in ticks if window["start"] < x < window["end"]]
    duration = window["end"] - window["start"]
    # With the GIL held for the call this loop could not run inside it (only at the switch
    # interval's edges); released, it ticks throughout: no pause longer than half the call.
    assert len(inside) > 100, (len(inside), duration)
    edges = [window["start"]] + inside + [window["end"]]
    longest = max(b - a for a, b in zip(edges, edges[1:]))
    assert longest < 0.5 * duration, (longest, duration)


def test_two_threads_get_the_same_numbers():
    frames = [frame_1080p(), np.ascontiguousarray(frame_1080p()[::2, ::2])]
    single = [infocus.analyze(f) for f in frames]
    results = [None, None]

    def run(i):
        results[i] = [infocus.analyze(frames[i]) for _ in range(3)]

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for i in range(2):
        for a in results[i]:
            np.testing.assert_array_equal(a.sharpness, single[i].sharpness)
            np.testing.assert_array_equal(a.blur_width_px, single[i].blur_width_px)
