# SPDX-License-Identifier: MIT
"""The `python` rows of `infocus bench`: infocus.analyze from Python on 1080p frames against the
common recipe (OpenCV's Laplacian variance per region in a Python loop), and the same frames
from two Python threads against one. Prints one JSON object."""
import json
import statistics
import sys
import threading
import time

COLS, ROWS = 16, 9


def median_ms(fn, budget_s):
    fn()  # warm-up
    times = []
    start = time.perf_counter()
    while len(times) < 5 or time.perf_counter() - start < budget_s:
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times)


def laplacian_grid(cv2, np, img):
    """The recipe infocus replaces: cv2.Laplacian(...).var() of each region, one at a time."""
    h, w = img.shape
    out = np.empty((ROWS, COLS))
    for r in range(ROWS):
        for c in range(COLS):
            region = img[r * h // ROWS:(r + 1) * h // ROWS, c * w // COLS:(c + 1) * w // COLS]
            out[r, c] = cv2.Laplacian(region, cv2.CV_64F).var()
    return out


def main():
    budget = float(sys.argv[1]) if len(sys.argv) > 1 else 0.25
    result = {}
    try:
        import numpy as np
        import infocus
    except ImportError as e:
        print(json.dumps({"error": f"cannot import {e.name}: build with -Dpython=enabled and "
                                   "install python3-numpy"}))
        return
    with infocus.open("sim:size=1920x1080,pace=fast,noise=0.01") as src:
        frames = [np.array(next(src).luma) for _ in range(8)]
    it = iter(range(1 << 62))

    def pick():
        return frames[next(it) % len(frames)]

    result["sharpness_ms"] = median_ms(lambda: infocus.analyze(pick(), blur=False), budget)
    result["full_ms"] = median_ms(lambda: infocus.analyze(pick()), budget)
    try:
        import cv2
        cv2.setNumThreads(1)  # one thread, as infocus's sharpness grid at 1080p
        result["recipe_ms"] = median_ms(lambda: laplacian_grid(cv2, np, pick()), budget)
    except ImportError:
        result["recipe_ms"] = None

    # The same 32 frames measured by one Python thread, then shared by two.
    work = frames * 4

    def run(chunk):
        for f in chunk:
            infocus.analyze(f, blur=False)

    def timed(threads):
        parts = [work[i::threads] for i in range(threads)]
        pool = [threading.Thread(target=run, args=(p,)) for p in parts]
        t0 = time.perf_counter()
        for t in pool:
            t.start()
        for t in pool:
            t.join()
        return (time.perf_counter() - t0) * 1e3 / len(work)

    timed(2)  # warm-up
    one = statistics.median(timed(1) for _ in range(3))
    two = statistics.median(timed(2) for _ in range(3))
    result["one_thread_ms"] = one
    result["two_threads_ms"] = two
    print(json.dumps(result))


if __name__ == "__main__":
    main()
