#!/usr/bin/env bash
# `infocus bench` as a user runs it: the JSON contract (docs/design.md, bench --json), every operator
# and the blur engine timed beside their baselines, and the blur engine's scalar and AVX2 kernels
# finding edges in the same regions. Timings are printed, never judged.
# Usage: test_bench.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
# The live rows run 0.5 s each here (20 s by default): enough to check their fields.
out=$("$bin" bench --json --seconds 0.01 --live-seconds 0.5)
st=$?
[[ $st -eq 0 ]] || {
	echo "FAIL: infocus bench --json exited $st"
	exit 1
}
echo "$out"
python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(line) for line in sys.argv[1].strip().split("\n")]
# The live rows: each case replayed through the live pipeline, infocus beside the baseline.
live = [r for r in rows if r["what"] == "live"]
cases = sorted((r["width"], r["height"], r["format"], r["nominal_fps"]) for r in live)
assert cases == [(1920, 1080, "MJPEG", 30), (1920, 1080, "YUYV", 60), (3840, 2160, "YUYV", 30)], cases
for r in live:
    assert r.get("baseline"), r
    for p in ("", "baseline_"):
        for k in ("fps", "frames", "dropped", "latency_p50_ms", "latency_p99_ms", "cpu_cores"):
            assert p + k in r, (p + k, r)
        assert r[p + "frames"] > 0 and r[p + "fps"] > 0 and r[p + "cpu_cores"] > 0, r
        assert 0 < r[p + "latency_p50_ms"] <= r[p + "latency_p99_ms"], r
    assert r["targets"] and all(isinstance(t["met"], bool) for t in r["targets"]), r
# The focusmeter rows: GRAY8 and I420 at 1080p60, each through focusmeter beside identity in
# the same run; without GStreamer built in they say so and measure nothing.
gst = [r for r in rows if r["what"] == "gstreamer"]
assert sorted((r["format"], r.get("interval_ns")) for r in gst) in (
    [("GRAY8", 0), ("GRAY8", 100000000), ("I420", 0), ("I420", 100000000)],
    [("GRAY8", None), ("I420", None)]), gst
for r in gst:
    assert (r["width"], r["height"], r["nominal_fps"]) == (1920, 1080, 60), r
    if "cpu_cores" not in r:
        assert "not built" in r["note"] or "not found" in r["note"], r
        continue
    assert r["baseline"] == "identity" and r["baseline_frames"] > 0, r
    assert r["frames_analysed"] > 0 and r["analysed_fps"] > 0, r
    assert r["cpu_cores"] > 0 and r["baseline_cpu_cores"] > 0, r
    assert abs(r["added_cores"] - (r["cpu_cores"] - r["baseline_cpu_cores"])) < 1e-9, r
    assert r["targets"] and all(isinstance(t["met"], bool) for t in r["targets"]), r
# The autofocus row: frames and errors of autofocus and of the contrast schedule, same runs.
af = [r for r in rows if r["what"] == "autofocus"]
assert len(af) == 1, af
a = af[0]
for k in ("frames_median", "frames_worst", "error_dpt_worst", "baseline_frames_median",
          "baseline_frames_worst", "baseline_error_dpt_worst"):
    assert k in a and a[k] >= 0, (k, a)
assert 0 < a["frames_median"] <= a["frames_worst"], a
assert 0 < a["baseline_frames_median"] <= a["baseline_frames_worst"], a
assert a["runs"] == 42 and 0 <= a["in_focus"] <= 42 and 0 <= a["baseline_in_focus"] <= 42, a
rows = [r for r in rows if r["what"] not in ("live", "gstreamer", "autofocus")]
for r in rows:
    for k in ("what", "width", "height", "ms"):
        assert k in r, (k, r)
    # The python rows need the module and Python: without them they say why, with no time.
    if r["what"].startswith("python") and r["ms"] == 0:
        assert "baseline_ms" not in r and r.get("note"), r
        continue
    assert r["ms"] > 0, r
    # A baseline comes with its speed-up, and the speed-up is the ratio of the two times.
    assert ("baseline_ms" in r) == ("speedup" in r), r
    if "baseline_ms" in r:
        assert r["baseline_ms"] > 0 and r.get("baseline"), r
        assert abs(r["speedup"] - r["baseline_ms"] / r["ms"]) <= 1e-9 * r["speedup"], r
jobs = [r for r in rows if r["what"] == "analyze_jobs"]
assert len(jobs) == 1 and "baseline_ms" in jobs[0] and "frames/s" in jobs[0]["note"], jobs
python = sorted(r["what"] for r in rows if r["what"].startswith("python"))
assert python == ["python", "python_threads"], python
full = [r for r in rows if r["what"] == "sharpness" and (r["width"], r["height"]) == (1920, 1080)]
ops = sorted(r["operator"] for r in full)
assert ops == sorted(["teng", "lapv", "lapm", "tenv", "brenner", "glvn", "dctr"]), ops
assert all("baseline_ms" in r for r in full)
blur = [r for r in rows if r["what"] == "blur"]
# Two frames: near focus (a 4 px disc) and well out of focus (12 px), each with its true blur.
assert sorted(r.get("frame_blur_width_px") for r in blur) == [4.0, 12.0], blur
for b in blur:
    assert (b["width"], b["height"]) == (1920, 1080) and "baseline_ms" in b, b
    # The scalar run (the same sums) finds edges in the same regions.
    assert "kernel bug" not in b["note"], b["note"]
    measured = int(b["note"].split(",")[1].split()[0])
    assert b["regions_with_edge"] == measured, b
    # The bench frame is textured all over: near focus every one of the 144 regions but a
    # handful has an edge; at 12 px the smaller leaves blur into each other and some regions
    # hold no edge with two plateaus.
    least = 120 if b["frame_blur_width_px"] == 4.0 else 80
    assert least <= measured <= 144, b["note"]
# The stream row: the tracker through a focus pull beside a full search of every frame; it must
# keep most of the search's regions and of its readings within 10 % of the true disc.
import re
stream = [r for r in rows if r["what"] == "blur_stream"]
assert len(stream) == 1 and (stream[0]["width"], stream[0]["height"]) == (1920, 1080), stream
s = stream[0]
assert "baseline_ms" in s, s
m = re.search(r"a frame: ([\d.]+) regions with an edge, ([\d.]+) within 10 % of the true disc, "
              r"([\d.]+) confident \(>= 0.25\), (\d+) % of those within 10 % "
              r"\(searching every frame: ([\d.]+), ([\d.]+), ([\d.]+), (\d+) %\)", s["note"])
assert m, s["note"]
regions, near, _, _, searched, searched_near, _, _ = map(float, m.groups())
assert searched >= 80 and searched_near >= 20, s["note"]  # the comparison is not empty
assert regions >= 0.8 * searched and near >= 0.8 * searched_near, s["note"]
PY
st=$?
[[ $st -eq 0 ]] && echo "ok" || echo "FAIL: bench JSON contract"
exit $st
