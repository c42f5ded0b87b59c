# SPDX-License-Identifier: MIT
"""A local cluster of two worker processes analyses the real photographs (the Pi sweep and both
stacks) into SQLite: every frame and region is there, every value is the one `infocus analyze`
prints (exactly: the numbers cross only as round-trip text), and `export` writes analyze's
rows."""
import json
import os

from conftest import run, table

SOURCES = ["focus-sweep-pi", "focus-stack/depthmap", "focus-stack/pcb"]
GRID = 16 * 9
REGION_FIELDS = ["sharpness", "edge_width_px", "blur_sigma_px", "blur_width_px", "mtf50_cy_px",
                 "mtf50p_cy_px", "confidence"]


def ordered(line):
    """A JSON line as nested (key, value) lists: equal only with the keys in the same order."""
    return json.loads(line, object_pairs_hook=list)


def test_real_photographs_on_two_workers(cli, batch, data_dir, tmp_path):
    db = str(tmp_path / "results.sqlite")
    r = run(batch + [data_dir, "-o", db, "--workers", "2", "--quiet"])
    assert r.returncode == 0, r.stderr
    ids = dict(table(db, "SELECT path, id FROM sources WHERE status = 'done'"))
    assert sorted(ids) == sorted(os.path.join(data_dir, s) for s in SOURCES)
    assert table(db, "PRAGMA journal_mode") == [("wal",)]
    for name in SOURCES:
        path = os.path.join(data_dir, name)
        sid = ids[path]
        jsonl = run([cli, "analyze", path, "--format", "jsonl"], check=True).stdout
        lines = [json.loads(line) for line in jsonl.splitlines()]
        # Row counts: frames, and frames x regions.
        assert table(db, "SELECT frames FROM sources WHERE id = ?", (sid,)) == [(len(lines),)]
        assert table(db, "SELECT COUNT(*) FROM frames WHERE source = ?", (sid,)) == \
            [(len(lines),)]
        assert table(db, "SELECT COUNT(*) FROM regions WHERE source = ?", (sid,)) == \
            [(len(lines) * GRID,)]
        # The values of the tables against analyze's, field by field, exactly.
        frames = {f[0]: f for f in table(
            db, "SELECT frame, timestamp_ns, frame_sharpness, noise_sigma, width, height "
            "FROM frames WHERE source = ?", (sid,))}
        regions = {(g[0], g[1], g[2]): g[3:] for g in table(
            db, f"SELECT frame, row, col, {', '.join(REGION_FIELDS)}, status FROM regions "
            "WHERE source = ?", (sid,))}
        for rec in lines:
            f = frames[rec["frame"]]
            assert f[1:] == (rec["timestamp_ns"], rec["frame_sharpness"],
                             rec.get("noise_sigma"), rec["width"], rec["height"]), name
            for g in rec["regions"]:
                got = regions[(rec["frame"], g["row"], g["col"])]
                want = tuple(g[k] for k in REGION_FIELDS) + (g["status"],)
                assert got == want, f"{name} frame {rec['frame']} region {g['col']},{g['row']}"
        # export writes analyze's rows: JSONL with the same keys in the same order and the same
        # numbers (a double may be spelled in more than one shortest way), CSV the same bytes.
        out = run(batch + ["export", db, "--format", "jsonl", "--source", path], check=True)
        assert [ordered(line) for line in out.stdout.splitlines()] == \
            [ordered(line) for line in jsonl.splitlines()], name
        csv = run([cli, "analyze", path, "--format", "csv"], check=True).stdout
        out = run(batch + ["export", db, "--format", "csv", "--source", path], check=True)
        assert out.stdout == csv, name
    # All sources at once: a leading source column, the rows of each source in path order.
    out = run(batch + ["export", db, "--format", "csv"], check=True).stdout.splitlines()
    assert out[0].startswith("source,frame,timestamp_ns,")
    counts = table(db, "SELECT COUNT(*) FROM regions")[0][0]
    assert len(out) == 1 + counts


def test_stack_table_matches_infocus_stack(cli, batch, data_dir, tmp_path):
    path = os.path.join(data_dir, "focus-stack", "pcb")
    db = str(tmp_path / "stack.sqlite")
    r = run(batch + [path, "-o", db, "--workers", "1", "--stack", "--quiet"])
    assert r.returncode == 0, r.stderr
    want = json.loads(run([cli, "stack", path, "--json"], check=True).stdout)
    a = want["agreement"]
    assert table(db, "SELECT frames, textured, both, agree FROM stacks") == \
        [(len(want["frames"]), a["textured"], a["both"], a["agree"])]
    rows = {(g[0], g[1]): g[2:] for g in table(
        db, "SELECT row, col, status, peak_frame, blur_peak_frame, agree FROM stack_regions")}
    assert len(rows) == len(want["regions"]) == 8 * 6
    for g in want["regions"]:
        assert rows[(g["row"], g["col"])] == (g["status"], g["peak_frame"],
                                              g["blur_peak_frame"],
                                              None if g["agree"] is None else int(g["agree"]))


def test_usage_errors_name_the_problem(batch, tmp_path):
    db = str(tmp_path / "r.sqlite")
    r = run(batch + [str(tmp_path / "missing"), "-o", db])
    assert r.returncode == 2 and "missing does not exist" in r.stderr, r.stderr
    r = run(batch + [str(tmp_path), "-o", db, "--grid", "0x9"])
    assert r.returncode == 2 and "0x9" in r.stderr, r.stderr
    r = run(batch + ["export", str(tmp_path / "none.sqlite")])
    assert r.returncode == 2 and "does not exist" in r.stderr, r.stderr
    r = run(batch + ["export", db, "--format", "xml"])
    assert r.returncode == 2 and "xml" in r.stderr, r.stderr
