#!/usr/bin/env python3
"""focusmeter on bad input through appsrc: a zero-size buffer, a buffer too short for its caps,
an odd stride given by a video meta (measured as the same pixels at the plain stride), a stride
shorter than a line, caps it cannot read (the error names them), a grid larger than the frame
(an error at caps time), and property values out of range (refused, the old value kept). Nothing
crashes, and the stream goes on after every bad buffer. Also attach-meta: one region meta per
cell carrying its frame's numbers.

Usage: test_bad_input.py PLUGIN_DIR. Skips (77) without python3-gi and the GStreamer
introspection data (gir1.2-gstreamer-1.0, gir1.2-gst-plugins-base-1.0)."""
import math
import os
import sys
import tempfile

SKIP = 77
os.environ["GST_PLUGIN_PATH"] = sys.argv[1]
os.environ["GST_REGISTRY"] = os.path.join(tempfile.mkdtemp(), "registry.bin")
try:
    import gi

    gi.require_version("Gst", "1.0")
    gi.require_version("GstVideo", "1.0")
    from gi.repository import Gst, GstVideo
except (ImportError, ValueError) as e:
    print(f"SKIP: GStreamer's Python bindings are missing ({e}): python3-gi, "
          "gir1.2-gstreamer-1.0, gir1.2-gst-plugins-base-1.0")
    sys.exit(SKIP)
Gst.init(None)
if Gst.ElementFactory.find("focusmeter") is None:
    print("FAIL: focusmeter not found")
    sys.exit(1)

fails = []


def check(cond, what):
    if not cond:
        fails.append(what)
        print("FAIL:", what)


def texture(w, h, stride):
    """A textured GRAY8 frame (crossed sine waves) laid out at @stride bytes a line."""
    out = bytearray(stride * h)
    for y in range(h):
        for x in range(w):
            out[y * stride + x] = int(128 + 50 * math.sin(x / 2.3) * math.cos(y / 3.1) +
                                      30 * math.sin((x + 2 * y) / 5.0))
    return out


def run(caps, buffers, props="grid=4x3 interval=0 skip-frames=false"):
    """Pushes @buffers through appsrc ! focusmeter ! fakesink; returns (messages, warnings, errors)
    as lists of structures and texts, having waited for EOS or an error."""
    p = Gst.parse_launch(f'appsrc name=src caps="{caps}" format=time ! focusmeter name=m {props} '
                         "! fakesink")
    src = p.get_by_name("src")
    p.set_state(Gst.State.PLAYING)
    for i, b in enumerate(buffers):
        b.pts = i * Gst.SECOND // 30
        b.duration = Gst.SECOND // 30
        src.emit("push-buffer", b)
    src.emit("end-of-stream")
    bus = p.get_bus()
    msgs, warns, errs = [], [], []
    while True:
        m = bus.timed_pop_filtered(30 * Gst.SECOND, Gst.MessageType.ANY)
        if m is None:
            errs.append("timeout: no EOS in 30 s")
            break
        if m.type == Gst.MessageType.ERROR:
            e, dbg = m.parse_error()
            errs.append(f"{e.message} {dbg}")
            break
        if m.type == Gst.MessageType.WARNING:
            w, dbg = m.parse_warning()
            warns.append(f"{w.message} {dbg}")
        if m.type == Gst.MessageType.EOS:
            break
        if m.type == Gst.MessageType.ELEMENT and m.get_structure().get_name() == "infocus":
            msgs.append(m.get_structure())
    p.set_state(Gst.State.NULL)
    return msgs, warns, errs


W, H = 63, 48  # GStreamer pads a GRAY8 line of 63 pixels to 64 bytes
GRAY = f"video/x-raw,format=GRAY8,width={W},height={H},framerate=30/1"
plain = texture(W, H, 64)

# A zero-size buffer, then a good one: a warning, the good one measured, no error.
msgs, warns, errs = run(GRAY, [Gst.Buffer.new(), Gst.Buffer.new_wrapped(bytes(plain))])
check(not errs, f"zero-size buffer: error {errs}")
check(len(msgs) == 1 and msgs[0].get_value("frame") == 1, "zero-size buffer: the next not measured")
check(any("0 bytes" in w and "63x48 GRAY8" in w for w in warns), f"zero-size buffer: warning {warns}")
reference = list(msgs[0].get_value("sharpness")) if msgs else []
check(len(reference) == 12 and all(x > 0 for x in reference), f"reference scores {reference}")

# The lines packed at 63 bytes without a video meta: shorter than the caps say.
msgs, warns, errs = run(GRAY, [Gst.Buffer.new_wrapped(bytes(texture(W, H, W))),
                               Gst.Buffer.new_wrapped(bytes(plain))])
check(not errs and len(msgs) == 1, f"short buffer: {len(msgs)} messages, errors {errs}")
check(any(f"{W * H} bytes" in w for w in warns), f"short buffer: warning {warns}")


def with_meta(data, stride):
    b = Gst.Buffer.new_wrapped(bytes(data))
    GstVideo.buffer_add_video_meta_full(b, GstVideo.VideoFrameFlags.NONE,
                                        GstVideo.VideoFormat.GRAY8, W, H, 1, [0, 0, 0, 0],
                                        [stride, 0, 0, 0])
    return b


# An odd stride (67) described by a video meta: the same pixels, the same numbers.
msgs, warns, errs = run(GRAY, [with_meta(texture(W, H, 67), 67)])
check(not errs and not warns and len(msgs) == 1, f"odd stride: {len(msgs)} msgs {warns} {errs}")
if msgs:
    got = list(msgs[0].get_value("sharpness"))
    check(len(got) == len(reference) and
          all(abs(a - b) <= 1e-12 * max(1.0, abs(b)) for a, b in zip(got, reference)),
          f"odd stride measures {got}, plain stride {reference}")

# A stride shorter than a line, and one that runs past the buffer: warned, passed on.
msgs, warns, errs = run(GRAY, [with_meta(texture(W, H, 67), 10),
                               with_meta(texture(W, H, 64), 200),
                               Gst.Buffer.new_wrapped(bytes(plain))])
check(not errs and len(msgs) == 1, f"bad stride: {len(msgs)} messages, errors {errs}")
check(any("stride" in w for w in warns), f"bad stride: warning {warns}")

# Caps it cannot read: negotiation fails, naming the format.
for caps, name in (("video/x-raw,format=RGB16,width=64,height=48,framerate=30/1", "RGB16"),
                   ("image/jpeg,width=64,height=48,framerate=30/1", "image/jpeg")):
    msgs, warns, errs = run(caps, [Gst.Buffer.new_wrapped(bytes(64 * 48 * 2))])
    # The source ends with not-negotiated; focusmeter says first what it cannot read.
    check(errs, f"caps {name}: no error")
    check(any("focusmeter cannot read" in m and name in m and "GRAY8" in m for m in warns + errs),
          f"caps {name}: messages {warns + errs}")
    check(not msgs, f"caps {name}: measured")

# A grid larger than the frame: an error at caps time naming both.
msgs, warns, errs = run("video/x-raw,format=GRAY8,width=8,height=8,framerate=30/1",
                        [Gst.Buffer.new_wrapped(bytes(64))], "grid=16x9")
check(errs and "grid 16x9" in errs[0] and "8x8" in errs[0], f"grid > frame: errors {errs}")
msgs, warns, errs = run("video/x-raw,format=GRAY8,width=8,height=8,framerate=30/1",
                        [Gst.Buffer.new_wrapped(bytes(64))], "roi=4,4,8,2")
check(errs and "roi 4,4,8,2" in errs[0], f"roi outside: errors {errs}")

# attach-meta with skip-frames=false: each buffer carries one region meta per grid cell, placed
# as the grid, whose parameters are its own frame's message's numbers.
p = Gst.parse_launch("videotestsrc num-buffers=3 ! video/x-raw,width=320,height=240 ! "
                     "focusmeter grid=2x2 interval=0 skip-frames=false attach-meta=true ! "
                     "fakesink name=s")
metas = []


def probe(pad, info):
    buf = info.get_buffer()
    for i in range(4):
        m = GstVideo.buffer_get_video_region_of_interest_meta_id(buf, i)
        s = m.get_param("infocus") if m else None
        metas.append((m.x, m.y, m.w, m.h, s.get_value("frame"), s.get_value("sharpness"))
                     if s else None)
    return Gst.PadProbeReturn.OK


p.get_by_name("s").get_static_pad("sink").add_probe(Gst.PadProbeType.BUFFER, probe)
p.set_state(Gst.State.PLAYING)
bus = p.get_bus()
scores = []
while True:
    m = bus.timed_pop_filtered(30 * Gst.SECOND, Gst.MessageType.ANY)
    if m is None or m.type in (Gst.MessageType.EOS, Gst.MessageType.ERROR):
        break
    if m.type == Gst.MessageType.ELEMENT and m.get_structure().get_name() == "infocus":
        scores.append(list(m.get_structure().get_value("sharpness")))
p.set_state(Gst.State.NULL)
check(len(metas) == 12 and None not in metas, f"attach-meta: metas {metas}")
if len(metas) == 12 and None not in metas and len(scores) == 3:
    for k, (x, y, w, h, frame, sharp) in enumerate(metas):
        f, i = divmod(k, 4)
        check((x, y, w, h) == (160 * (i % 2), 120 * (i // 2), 160, 120), f"meta {k} at {x},{y}")
        same = sharp == scores[f][i] or (math.isnan(sharp) and math.isnan(scores[f][i]))
        check(frame == f and same, f"meta {k}: frame {frame}, {sharp}")

# Out-of-range values: refused, the old value kept.
m = Gst.ElementFactory.make("focusmeter", None)
for name, value, kept in (("blur-search", 70000, 16), ("grid", "300x2", "16x9"),
                          ("grid", "4x", "16x9"), ("roi", "1,2,3", ""), ("roi", "0,0,0,5", ""),
                          ("focus-distance", -1.0, 0.0), ("f-number", 5000.0, 0.0),
                          ("pixel-pitch", math.nan, 0.0)):
    try:
        m.set_property(name, value)
    except (TypeError, ValueError, OverflowError):
        pass  # the bindings may refuse it before GLib does
    check(m.get_property(name) == kept, f"{name}={value!r} changed it to {m.get_property(name)!r}")
m.set_property("grid", "4x3")
check(m.get_property("grid") == "4x3", "a valid grid refused")

if fails:
    print(f"{len(fails)} check(s) failed")
    sys.exit(1)
print("all bad-input checks passed")
