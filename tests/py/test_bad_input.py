# SPDX-License-Identifier: MIT
"""Bad input raises ValueError or TypeError with a message that says what and what to do, and
never crashes the interpreter: one row per case."""
import numpy as np
import pytest

import infocus

GOOD = np.full((48, 64), 128, np.uint8)
FLOAT_NAN = np.full((48, 64), 100.0, np.float32)
FLOAT_NAN[3, 5] = np.nan
FLOAT_INF = np.full((48, 64), 100.0, np.float32)
FLOAT_INF[0, 0] = np.inf


def closed_source():
    s = infocus.open("sim:size=64x48")
    s.close()
    return s


FRAMES = [
    # (name, frame, exception, words the message must hold)
    ("3-D array", np.zeros((48, 64, 3), np.uint8), ValueError, "not a 2-D image"),
    ("1-D array", np.zeros(64, np.uint8), ValueError, "not a 2-D image"),
    ("0-D array", np.array(5, np.uint8), ValueError, "not a 2-D image"),
    ("empty rows", np.zeros((0, 64), np.uint8), ValueError, "is empty"),
    ("empty columns", np.zeros((48, 0), np.uint8), ValueError, "is empty"),
    ("int32", np.zeros((48, 64), np.int32), TypeError, "dtype int32"),
    ("float64", np.zeros((48, 64), np.float64), TypeError, "dtype float64"),
    ("bool", np.zeros((48, 64), bool), TypeError, "dtype bool"),
    ("int8", np.zeros((48, 64), np.int8), TypeError, "dtype int8"),
    ("big-endian uint16", np.zeros((48, 64), ">u2"), TypeError, "not a luma type"),
    ("object array", np.full((48, 64), None, object), TypeError, "dtype object"),
    ("NaN pixel", FLOAT_NAN, ValueError, "pixel (5, 3) is NaN"),
    ("infinite pixel", FLOAT_INF, ValueError, "pixel (0, 0) is infinite"),
    ("rows flipped", GOOD[::-1], ValueError, "negative strides"),
    ("columns flipped", GOOD[:, ::-1], ValueError, "negative strides"),
    ("a list", [[1, 2], [3, 4]], TypeError, "got list"),
    ("a string", "frame.png", TypeError, "got str"),
    ("None", None, TypeError, "got NoneType"),
]


@pytest.mark.parametrize("name,frame,error,words", FRAMES, ids=[f[0] for f in FRAMES])
def test_bad_frame(name, frame, error, words):
    with pytest.raises(error) as e:
        infocus.analyze(frame)
    assert words in str(e.value)


OPTIONS = [
    ("grid of 0 columns", dict(grid=(0, 9)), ValueError, "grid"),
    ("grid past 256", dict(grid=(300, 9)), ValueError, "256"),
    ("grid past the frame", dict(grid=(100, 9)), ValueError, ""),
    ("unknown metric", dict(metric="sobel"), ValueError, "sobel"),
    ("ROI outside the frame", dict(roi=[(60, 40, 32, 32)]), ValueError, ""),
    ("ROI of no size", dict(roi=[(0, 0, 0, 10)]), ValueError, ""),
    ("unknown transfer", dict(transfer="gamma"), ValueError, "linear, srgb, rec709"),
    ("lens without pitch", dict(lens=infocus.Lens(4e-3, 2.0, focus=1.0)), ValueError,
     "pixel pitch"),
    ("lens without focus", dict(lens=infocus.Lens(4e-3, 2.0, pixel_pitch=2e-6)), ValueError,
     "focus distance"),
    ("grid not a pair", dict(grid=16), TypeError, "incompatible"),
]


@pytest.mark.parametrize("name,kwargs,error,words", OPTIONS, ids=[o[0] for o in OPTIONS])
def test_bad_option(name, kwargs, error, words):
    with pytest.raises(error) as e:
        infocus.analyze(GOOD, **kwargs)
    assert words in str(e.value)
    assert len(str(e.value)) > 20  # a sentence, not a code


SOURCES = [
    ("unknown kind", "nope:x", ValueError, "does not exist"),
    ("empty string", "", ValueError, ""),
    ("missing file", "/nonexistent/frame.png", ValueError, "/nonexistent/frame.png"),
    ("unknown sim option", "sim:colour=red", ValueError, "colour"),
    ("duplicated option", "sim:size=64x48,size=32x32", ValueError, "size"),
    ("bad sim size", "sim:size=0x0", ValueError, "size"),
    ("not a string", 42, TypeError, "incompatible"),
]


@pytest.mark.parametrize("name,text,error,words", SOURCES, ids=[s[0] for s in SOURCES])
def test_bad_source(name, text, error, words):
    with pytest.raises(error) as e:
        infocus.open(text)
    assert words in str(e.value)


CLOSED = [
    ("next", lambda s: next(s)),
    ("info", lambda s: s.info),
    ("focus", lambda s: s.focus),
    ("stats", lambda s: s.stats),
]


@pytest.mark.parametrize("name,use", CLOSED, ids=[c[0] for c in CLOSED])
def test_closed_source(name, use):
    s = closed_source()
    with pytest.raises(ValueError) as e:
        use(s)
    assert "is closed" in str(e.value) and "infocus.open" in str(e.value)
    s.close()  # twice is fine


def test_focus_control_of_a_closed_source():
    s = infocus.open("sim:size=64x48")
    focus = s.focus
    s.close()
    with pytest.raises(ValueError, match="is closed"):
        focus.get()


OPTICS = [
    ("zero focal length", lambda: infocus.Lens(0.0, 2.0), ValueError, "focal length"),
    ("NaN f-number", lambda: infocus.Lens(50e-3, float("nan")), ValueError, "f-number"),
    ("negative pitch", lambda: infocus.Lens(50e-3, 2.0, pixel_pitch=-1e-6), ValueError,
     "pixel_pitch"),
    ("unknown preset", lambda: infocus.Lens.preset("hasselblad"), ValueError, "rpi-cam3"),
    ("dof without focus", lambda: infocus.Lens(50e-3, 8.0, coc=30e-6).depth_of_field(),
     ValueError, "focus distance"),
    ("dof without coc", lambda: infocus.Lens(50e-3, 8.0, focus=2.0).depth_of_field(),
     ValueError, "circle of confusion"),
    ("dof inside f", lambda: infocus.Lens(50e-3, 8.0, coc=30e-6).depth_of_field(focus=0.01),
     ValueError, "too close"),
    ("blur given twice", lambda: infocus.Lens(50e-3, 8.0, pixel_pitch=5e-6, focus=2.0)
     .depth_from_blur(blur=1e-5, blur_px=2), ValueError, "one way"),
    ("blur_px without pitch", lambda: infocus.Lens(50e-3, 8.0, focus=2.0)
     .depth_from_blur(blur_px=2), ValueError, "pixel_pitch"),
]


@pytest.mark.parametrize("name,call,error,words", OPTICS, ids=[o[0] for o in OPTICS])
def test_bad_optics(name, call, error, words):
    with pytest.raises(error) as e:
        call()
    assert words in str(e.value)


def test_bad_stack_source():
    with pytest.raises(ValueError, match="nope"):
        infocus.stack("nope:x")


def test_stack_of_too_few_frames(data_dir):
    with pytest.raises(ValueError, match="at least 3"):
        infocus.stack(data_dir + "/focus-stack/pcb/pcb_001.jpg")
