# SPDX-License-Identifier: MIT
"""The rest of the module against formulas, the simulated camera and the command line."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import infocus


def test_frames_of_the_simulated_camera():
    with infocus.open("sim:size=320x240,focus=1m") as src:
        assert src.info["width"] == 320 and src.info["driver"] == "sim"
        frames = [next(src) for _ in range(3)]
    for i, f in enumerate(frames):
        assert f.luma.shape == (240, 320) and f.luma.dtype == np.uint8
        assert not f.luma.flags.writeable
        assert f.index == i
        assert f.lens is not None and f.lens.dioptres == pytest.approx(1.0, abs=1e-9)
    assert frames[1].timestamp > frames[0].timestamp
    assert frames[2].sequence > frames[1].sequence


def test_luma_outlives_its_source():
    with infocus.open("sim:size=64x48") as src:
        luma = next(src).luma
    assert int(luma.sum()) > 0  # the view keeps its frame alive after close()


def test_focus_control_moves_the_simulated_lens():
    with infocus.open("sim:size=160x120,focus=1m") as src:
        focus = src.focus
        assert focus is not None and focus.range.unit == "dioptre"
        focus.set(2.0)
        assert focus.get().dioptres == pytest.approx(2.0, abs=1e-9)
        for _ in range(focus.settle_frames + 1):
            f = next(src)
        assert f.lens.dioptres == pytest.approx(2.0, abs=1e-9)


def test_files_have_no_focus_control(data_dir):
    with infocus.open(os.path.join(data_dir, "focus-sweep-pi")) as src:
        assert src.focus is None


def test_depth_of_field_by_formula():
    f, n, c, u = 50e-3, 8.0, 30e-6, 10.0
    d = infocus.Lens(f, n, coc=c).depth_of_field(focus=u)
    # Exact thin-lens limits: near = u f^2/(f^2 + N c (u - f)), far = u f^2/(f^2 - N c (u - f)).
    assert d.near == pytest.approx(u * f * f / (f * f + n * c * (u - f)), rel=1e-12)
    assert d.far == pytest.approx(u * f * f / (f * f - n * c * (u - f)), rel=1e-12)
    assert d.hyperfocal == pytest.approx(f * f / (n * c) + f, rel=1e-12)
    assert infocus.Lens(f, n, coc=c).depth_of_field(focus=d.hyperfocal).far == math.inf


def test_depth_from_blur_inverts_the_blur_model():
    lens = infocus.Lens(4.74e-3, 1.8, pixel_pitch=1.4e-6, focus=0.5)
    for z in (0.3, 0.4, 0.8, 2.0):
        b = lens.blur_width(z)
        # Thin lens: b = A |z_s (1/f - 1/z) - 1| with z_s = f u/(u - f).
        zs = lens.focal_length * 0.5 / (0.5 - lens.focal_length)
        assert b == pytest.approx(lens.aperture * abs(zs * (1 / lens.focal_length - 1 / z) - 1),
                                  rel=1e-12)
        roots = lens.depth_from_blur(blur=b)
        found = roots.near if z < 0.5 else roots.far
        assert found == pytest.approx(z, rel=1e-9)
        px = lens.depth_from_blur(blur_px=b / 1.4e-6)
        assert px.near == pytest.approx(roots.near, rel=1e-12)


def test_analysis_depths_follow_the_lens():
    with infocus.open("sim:scene=plane,distance=0.7m,focus=0.5m,size=640x480") as src:
        frame = next(src)
    lens = infocus.Lens.preset("rpi-cam3", focus=0.5)
    a = infocus.analyze(frame, grid=(8, 6), lens=lens)
    assert a.focus_distance_m == 0.5
    near, far, width = a.depth_near_m, a.depth_far_m, a.blur_width_px
    used = ~np.isnan(near)
    assert used.sum() >= 10
    for r, c in zip(*np.nonzero(used)):
        roots = lens.depth_from_blur(blur_px=width[r, c])
        assert near[r, c] == pytest.approx(roots.near, rel=1e-12)
        assert far[r, c] == pytest.approx(roots.far if roots.far is not None else math.nan,
                                          rel=1e-12, nan_ok=True)
    # The plane is 0.7 m away, behind the focus: its far roots sit near 0.7 m.
    assert np.nanmedian(far[used]) == pytest.approx(0.7, rel=0.25)


def test_analyze_source_reports_progress(data_dir):
    calls = []
    out = infocus.analyze_source(os.path.join(data_dir, "focus-stack/pcb"), grid=(4, 3),
                                 blur=False, progress=lambda done, total: calls.append((done, total)))
    assert [c[0] for c in calls] == list(range(1, len(out) + 1))
    assert all(total == len(out) for _, total in calls)


def test_a_raising_callback_stops_the_call(data_dir):
    def boom(done, total):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        infocus.analyze_source(os.path.join(data_dir, "focus-sweep-pi"), grid=(2, 2),
                               blur=False, progress=boom)


def test_stack_matches_the_cli(cli, data_dir):
    source = os.path.join(data_dir, "focus-stack/pcb")
    expected = json.loads(subprocess.run([cli, "stack", source, "--json"], check=True,
                                         capture_output=True, text=True).stdout)
    calls = []
    got = infocus.stack(source, progress=lambda d, t: calls.append((d, t)))
    n = len(expected["frames"])
    assert calls[-1] == (n, n) and len(calls) == n
    for key in ("width", "height", "metric", "axis_unit", "agreement"):
        assert got[key] == expected[key]
    for a, b in zip(got["regions"], expected["regions"]):
        assert a["status"] == b["status"]
        assert (a["peak_frame"] is None) == (b["peak_frame"] is None)
        if a["peak_frame"] is not None:
            assert a["peak_frame"] == pytest.approx(b["peak_frame"], abs=1e-9)
        # The arrays hold the curves the dict lists.
        curve = got["sharpness_curves"][a["row"], a["col"]]
        listed = [math.nan if v is None else v for v in b["curve"]["sharpness"]]
        np.testing.assert_allclose(curve, listed, rtol=1e-9, equal_nan=True)
    assert got["composite"].shape == (got["height"], got["width"])
    assert got["focus_map_array"].shape == (expected["focus_map"]["rows"],
                                            expected["focus_map"]["cols"])


def test_the_blur_threads_do_not_change_the_results(data_dir):
    # One thread (a Dask worker's share) and one per core measure the same edges.
    with infocus.open(os.path.join(data_dir, "focus-stack/pcb")) as src:
        frame = np.array(next(src).luma)
    one = infocus.analyze(frame, grid=(8, 6), threads=1)
    every = infocus.analyze(frame, grid=(8, 6), threads=0)
    assert np.isfinite(one.blur_width_px).sum() >= 10  # the frame has edges to share out
    assert one.to_json() == every.to_json()
    with pytest.raises(TypeError):
        infocus.analyze(frame, threads=-1)
