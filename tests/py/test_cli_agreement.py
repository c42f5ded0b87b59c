# SPDX-License-Identifier: MIT
"""infocus.analyze gives the numbers `infocus analyze --format jsonl` prints, on every frame of
the real photographs, field by field to 1e-9 (relative, absolute under 1)."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import infocus

TOLERANCE = 1e-9
SOURCES = ["focus-sweep-pi", "focus-stack/depthmap", "focus-stack/pcb"]
REGION_FIELDS = ["sharpness", "edge_width_px", "blur_sigma_px", "blur_width_px", "confidence"]


def close(a, b):
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) <= TOLERANCE * max(1.0, abs(a), abs(b))


def value(x):
    """A NumPy cell as the JSONL writes it: NaN is null."""
    x = float(x)
    return None if math.isnan(x) else x


def cli_lines(cli, source):
    out = subprocess.run([cli, "analyze", source, "--format", "jsonl"],
                         check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def compare(record, a, label):
    assert a.width == record["width"] and a.height == record["height"], label
    assert a.metric == record["metric"], label
    assert close(a.frame_sharpness, record["frame_sharpness"]), label
    assert close(a.noise_sigma, record.get("noise_sigma")), label
    assert len(record["regions"]) == a.sharpness.size, label
    status = a.status
    for reg in record["regions"]:
        r, c = reg["row"], reg["col"]
        assert status[r, c] == reg["status"], f"{label} region {c},{r}"
        assert list(a.rects[r, c]) == [reg["x"], reg["y"], reg["w"], reg["h"]]
        for field in REGION_FIELDS:
            got = value(getattr(a, field)[r, c])
            assert close(got, reg[field]), f"{label} region {c},{r} {field}: {got} != {reg[field]}"


@pytest.mark.parametrize("name", SOURCES)
def test_every_frame_matches_the_cli(cli, data_dir, name):
    source = os.path.join(data_dir, name)
    lines = cli_lines(cli, source)
    assert len(lines) >= 7
    n = 0
    with infocus.open(source) as src:
        for frame, record in zip(src, lines):
            label = f"{name} frame {frame.index} ({os.path.basename(frame.origin)})"
            # The frame as the source delivered it (JPEG bytes, luma decoded by the library) ...
            a = infocus.analyze(frame)
            assert a.frame == record["frame"]
            compare(record, a, label)
            # ... and its luma handed over as a NumPy array: the same pixels, the same numbers.
            compare(record, infocus.analyze(frame.luma), label + " as an array")
            n += 1
    assert n == len(lines)


def test_analyze_source_matches_the_cli(cli, data_dir):
    source = os.path.join(data_dir, "focus-sweep-pi")
    lines = cli_lines(cli, source)
    results = infocus.analyze_source(source)
    assert len(results) == len(lines)
    for record, a in zip(lines, results):
        assert a.frame == record["frame"]
        compare(record, a, f"frame {a.frame}")
        assert json.loads(a.to_json()) == record


def test_layouts_give_the_same_numbers(data_dir):
    with infocus.open(os.path.join(data_dir, "focus-sweep-pi")) as src:
        luma = np.array(next(src).luma)
    ref = infocus.analyze(luma)
    wide = np.zeros((luma.shape[0], luma.shape[1] * 2), np.uint8)
    wide[:, ::2] = luma
    variants = {
        "row-padded view": np.pad(luma, ((0, 0), (0, 24)))[:, : luma.shape[1]],
        "column-strided view": wide[:, ::2],
        "Fortran order": np.asfortranarray(luma),
        "uint16 x 257": luma.astype(np.uint16) * 257,
        "float32 grey levels": luma.astype(np.float32),
    }
    for name, frame in variants.items():
        a = infocus.analyze(frame)
        for field in REGION_FIELDS:
            np.testing.assert_allclose(getattr(a, field), getattr(ref, field), rtol=1e-12,
                                       atol=0, equal_nan=True, err_msg=name)
        assert a.frame_sharpness == pytest.approx(ref.frame_sharpness, rel=1e-12), name
