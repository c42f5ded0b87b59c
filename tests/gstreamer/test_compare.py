#!/usr/bin/env python3
"""focusmeter measures what `infocus analyze` measures: the pcb focus stack's JPEG files through
multifilesrc ! jpegdec ! focusmeter, each `infocus` message read from the bus, against the
JSONL analyze writes for the same files. Scores, sharpness, blur width and confidence agree
within 1e-6 (relative, 1e-6 absolute near 0); status and the grid exactly.

Usage: test_compare.py INFOCUS PLUGIN_DIR SHARED_DATA_DIR. Skips (77) without python3-gi and
gir1.2-gstreamer-1.0, or without jpegdec (gstreamer1.0-plugins-good)."""
import json
import math
import os
import subprocess
import sys
import tempfile

SKIP = 77
infocus, plugin_dir, data = sys.argv[1:4]
os.environ["GST_PLUGIN_PATH"] = plugin_dir
tmp = tempfile.mkdtemp()
os.environ["GST_REGISTRY"] = os.path.join(tmp, "registry.bin")

try:
    import gi

    gi.require_version("Gst", "1.0")
    from gi.repository import Gst
except (ImportError, ValueError) as e:
    print(f"SKIP: GStreamer's Python bindings are missing ({e}): python3-gi, gir1.2-gstreamer-1.0")
    sys.exit(SKIP)

Gst.init(None)
for name in ("multifilesrc", "jpegdec", "fakesink"):
    if Gst.ElementFactory.find(name) is None:
        print(f"SKIP: element {name} missing (gstreamer1.0-plugins-base/-good)")
        sys.exit(SKIP)
if Gst.ElementFactory.find("focusmeter") is None:
    print(f"FAIL: focusmeter not found in {plugin_dir}")
    sys.exit(1)

stack = os.path.join(data, "focus-stack", "pcb")
files = sorted(f for f in os.listdir(stack) if f.startswith("pcb_") and f.endswith(".jpg"))
if not files:
    print(f"SKIP: no pcb_*.jpg in {stack}")
    sys.exit(SKIP)
GRID = (8, 6)

# What analyze writes, one JSON object per file, in name order.
out = subprocess.run([infocus, "analyze", os.path.join(stack, "pcb_*.jpg"), "--grid",
                      f"{GRID[0]}x{GRID[1]}", "--blur-search", "all"],
                     capture_output=True, text=True, check=True)
expected = [json.loads(line) for line in out.stdout.splitlines() if line.strip()]
assert len(expected) == len(files), (len(expected), len(files))


def read_messages(pipeline_text):
    """Runs the pipeline to EOS and returns its infocus messages' structures."""
    pipeline = Gst.parse_launch(pipeline_text)
    bus = pipeline.get_bus()
    pipeline.set_state(Gst.State.PLAYING)
    got = []
    while True:
        msg = bus.timed_pop_filtered(120 * Gst.SECOND, Gst.MessageType.ANY)
        if msg is None:
            raise SystemExit("FAIL: no EOS within 120 s")
        if msg.type == Gst.MessageType.ERROR:
            err, dbg = msg.parse_error()
            raise SystemExit(f"FAIL: pipeline error: {err.message} ({dbg})")
        if msg.type == Gst.MessageType.EOS:
            break
        if msg.type == Gst.MessageType.ELEMENT and msg.get_structure().get_name() == "infocus":
            got.append(msg.get_structure())
    pipeline.set_state(Gst.State.NULL)
    return got


def close(a, b, what):
    """a (message) equals b (analyze) within 1e-6; NaN in the message stands for JSON null."""
    if b is None:
        if not math.isnan(a):
            raise AssertionError(f"{what}: message {a}, analyze null")
        return
    if abs(a - b) > 1e-6 * max(1.0, abs(b)):
        raise AssertionError(f"{what}: message {a!r}, analyze {b!r}")


first = int(files[0][4:7])
msgs = read_messages(
    f'multifilesrc location="{stack}/pcb_%03d.jpg" start-index={first} '
    f"stop-index={first + len(files) - 1} caps=image/jpeg,framerate=1/1 ! jpegdec idct-method=islow ! "
    f"focusmeter grid={GRID[0]}x{GRID[1]} blur-search=0 interval=0 skip-frames=false ! fakesink")
assert len(msgs) == len(files), f"{len(msgs)} messages for {len(files)} files"

compared = 0
for i, (s, e) in enumerate(zip(msgs, expected)):
    where = f"{files[i]}"
    assert s.get_value("frame") == i, (where, s.get_value("frame"))
    assert s.get_value("skipped") == 0, where
    assert (s.get_value("cols"), s.get_value("rows")) == GRID, where
    assert (s.get_value("width"), s.get_value("height")) == (e["width"], e["height"]), where
    assert s.get_value("metric") == e["metric"], where
    assert s.get_value("timestamp") == i * Gst.SECOND, (where, s.get_value("timestamp"))
    close(s.get_value("score"), e["frame_sharpness"], f"{where} score")
    sharp = list(s.get_value("sharpness"))
    blur = list(s.get_value("blur-width-px"))
    conf = list(s.get_value("confidence"))
    status = list(s.get_value("status"))
    regions = e["regions"]
    assert len(sharp) == len(blur) == len(conf) == len(status) == len(regions) == GRID[0] * GRID[1]
    for k, r in enumerate(regions):
        # Row-major: index = row * cols + col, as analyze orders its regions.
        assert k == r["row"] * GRID[0] + r["col"], (where, k)
        w = f"{where} region {r['col']},{r['row']}"
        assert status[k] == r["status"], (w, status[k], r["status"])
        close(sharp[k], r["sharpness"], w + " sharpness")
        close(blur[k], r["blur_width_px"], w + " blur-width-px")
        close(conf[k], r["confidence"], w + " confidence")
        compared += 1
    pct = s.get_value("percent-of-peak")
    peak = max(x["frame_sharpness"] for x in expected[: i + 1])
    close(pct, 100.0 * e["frame_sharpness"] / peak, f"{where} percent-of-peak")

with_blur = sum(1 for e in expected for r in e["regions"] if r["blur_width_px"] is not None)
print(f"{len(msgs)} frames, {compared} regions ({with_blur} with a blur width) agree with "
      f"infocus analyze within 1e-6")
