# SPDX-License-Identifier: MIT
"""The results database (SQLite, WAL). Only the client writes it, one transaction per source, so
the file holds whole sources whenever it is read or the client is killed."""
import json
import os
import sqlite3
import time

SCHEMA = """
CREATE TABLE IF NOT EXISTS sources (
    id INTEGER PRIMARY KEY,
    path TEXT NOT NULL UNIQUE,          -- absolute; valid on the client and every worker
    size INTEGER,                       -- bytes of the source's files
    mtime_ns INTEGER,                   -- newest mtime of its files
    hash TEXT,                          -- BLAKE2b-128 of its files' names and bytes
    kind TEXT,                          -- recording, video, image, images, glob
    frames INTEGER,                     -- frames analysed
    status TEXT NOT NULL CHECK (status IN ('queued', 'done', 'failed')),
    error TEXT,                         -- the library's message when failed
    started REAL,                       -- Unix time queued
    finished REAL,                      -- Unix time written
    infocus_version TEXT,
    grid TEXT,                          -- CxR it was analysed with
    stack INTEGER NOT NULL DEFAULT 0,   -- 1 when --stack
    worker_seconds REAL                 -- its tasks' time on the workers, summed
);
CREATE INDEX IF NOT EXISTS sources_status ON sources (status);
CREATE TABLE IF NOT EXISTS frames (
    source INTEGER NOT NULL REFERENCES sources (id) ON DELETE CASCADE,
    frame INTEGER NOT NULL,
    timestamp_ns INTEGER NOT NULL,
    width INTEGER NOT NULL,
    height INTEGER NOT NULL,
    metric TEXT,
    frame_sharpness REAL,               -- NULL when no region is ok
    noise_sigma REAL,
    noise_reason TEXT,
    lens_value REAL,
    lens_unit TEXT,
    lens_dioptres REAL,
    PRIMARY KEY (source, frame)
) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS regions (
    source INTEGER NOT NULL REFERENCES sources (id) ON DELETE CASCADE,
    frame INTEGER NOT NULL,
    row INTEGER NOT NULL,
    col INTEGER NOT NULL,
    x INTEGER NOT NULL, y INTEGER NOT NULL, w INTEGER NOT NULL, h INTEGER NOT NULL,
    sharpness REAL,
    edge_width_px REAL,                 -- 10-90 % edge rise
    blur_sigma_px REAL,                 -- Gaussian-equivalent sigma
    blur_width_px REAL,                 -- disc-equivalent diameter
    mtf50_cy_px REAL,
    mtf50p_cy_px REAL,
    confidence REAL NOT NULL,
    status TEXT NOT NULL,
    reason TEXT,
    PRIMARY KEY (source, frame, row, col)
) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS stacks (
    source INTEGER PRIMARY KEY REFERENCES sources (id) ON DELETE CASCADE,
    metric TEXT,
    axis_unit TEXT,
    position_unit TEXT,
    frames INTEGER,
    textured INTEGER,                   -- agreement: textured regions,
    both INTEGER,                       -- those with a peak and a blur vertex,
    agree INTEGER                       -- and those whose two agree
);
CREATE TABLE IF NOT EXISTS stack_regions (
    source INTEGER NOT NULL REFERENCES sources (id) ON DELETE CASCADE,
    row INTEGER NOT NULL,
    col INTEGER NOT NULL,
    x INTEGER, y INTEGER, w INTEGER, h INTEGER,
    status TEXT,
    status_reason TEXT,
    peak_frame REAL,                    -- sharpness peak, fractional frame
    peak_position REAL,
    peak_dioptres REAL,
    at_end INTEGER,
    blur_peak_frame REAL,               -- vertex of the blur-width V
    vertex_position REAL,
    vertex_slope_px_per_unit REAL,
    vertex_rms_px REAL,
    vertex_points INTEGER,
    agree INTEGER,
    in_focus_distance_m REAL,
    PRIMARY KEY (source, row, col)
) WITHOUT ROWID;
"""

REGION_FIELDS = ("sharpness", "edge_width_px", "blur_sigma_px", "blur_width_px", "mtf50_cy_px",
                 "mtf50p_cy_px")


class Store:
    """The database at @p path, created with its tables when new."""

    def __init__(self, path):
        self.path = path
        # Autocommit: every write below is inside an explicit BEGIN ... COMMIT.
        self.db = sqlite3.connect(path, isolation_level=None, timeout=60)
        self.db.execute("PRAGMA journal_mode = WAL")
        self.db.execute("PRAGMA foreign_keys = ON")
        self.db.execute("PRAGMA synchronous = NORMAL")  # WAL: a commit survives a crash of us
        self.db.executescript(SCHEMA)

    def close(self):
        self.db.close()

    def previous(self, path):
        """(size, mtime_ns, hash, grid, stack) of a source stored complete, or None."""
        return self.db.execute(
            "SELECT size, mtime_ns, hash, grid, stack FROM sources WHERE path = ? AND "
            "status = 'done'", (path,)).fetchone()

    def _id(self, path):
        row = self.db.execute("SELECT id FROM sources WHERE path = ?", (path,)).fetchone()
        return row[0] if row else None

    def _clear(self, sid):
        for table in ("regions", "frames", "stack_regions", "stacks"):
            self.db.execute(f"DELETE FROM {table} WHERE source = ?", (sid,))

    def queue(self, entries):
        """Marks (path, kind, size, mtime_ns) entries as queued, dropping any older rows of
        theirs, in one transaction."""
        now = time.time()
        self.db.execute("BEGIN IMMEDIATE")
        try:
            for path, kind, size, mtime in entries:
                sid = self._id(path)
                if sid is None:
                    self.db.execute(
                        "INSERT INTO sources (path, kind, size, mtime_ns, status, started) "
                        "VALUES (?, ?, ?, ?, 'queued', ?)", (path, kind, size, mtime, now))
                    continue
                self._clear(sid)
                self.db.execute(
                    "UPDATE sources SET kind = ?, size = ?, mtime_ns = ?, hash = NULL, "
                    "frames = NULL, status = 'queued', error = NULL, started = ?, finished = NULL,"
                    " infocus_version = NULL, worker_seconds = NULL WHERE id = ?",
                    (kind, size, mtime, now, sid))
            self.db.execute("COMMIT")
        except BaseException:
            self.db.execute("ROLLBACK")
            raise

    def fail(self, path, error, version=None):
        """Records the source as failed with @p error, without rows."""
        self.db.execute("BEGIN IMMEDIATE")
        try:
            sid = self._id(path)
            self._clear(sid)
            self.db.execute(
                "UPDATE sources SET status = 'failed', error = ?, frames = NULL, finished = ?, "
                "infocus_version = ? WHERE id = ?", (error, time.time(), version, sid))
            self.db.execute("COMMIT")
        except BaseException:
            self.db.execute("ROLLBACK")
            raise

    def complete(self, path, records, digest, version, grid, stack=None, seconds=None):
        """Writes the source's frames (the records of `infocus analyze`, parsed, in order), their
        regions and the stack when given, and marks it done: one transaction."""
        self.db.execute("BEGIN IMMEDIATE")
        try:
            sid = self._id(path)
            self._clear(sid)
            frames, regions = [], []
            for r in records:
                lens = r.get("lens_position") or {}
                frames.append((sid, r["frame"], r["timestamp_ns"], r["width"], r["height"],
                               r.get("metric"), r.get("frame_sharpness"), r.get("noise_sigma"),
                               r.get("noise_reason"), lens.get("value"), lens.get("unit"),
                               lens.get("dioptres")))
                for g in r["regions"]:
                    regions.append((sid, r["frame"], g["row"], g["col"], g["x"], g["y"], g["w"],
                                    g["h"], *(g.get(k) for k in REGION_FIELDS), g["confidence"],
                                    g["status"], g.get("reason")))
            self.db.executemany(f"INSERT INTO frames VALUES ({','.join('?' * 12)})", frames)
            self.db.executemany(f"INSERT INTO regions VALUES ({','.join('?' * 17)})", regions)
            if stack is not None:
                self._stack(sid, json.loads(stack))
            self.db.execute(
                "UPDATE sources SET status = 'done', error = NULL, hash = ?, frames = ?, "
                "finished = ?, infocus_version = ?, grid = ?, stack = ?, worker_seconds = ? "
                "WHERE id = ?", (digest, len(frames), time.time(), version, grid,
                                 int(stack is not None), seconds, sid))
            self.db.execute("COMMIT")
        except BaseException:
            self.db.execute("ROLLBACK")
            raise

    def _stack(self, sid, s):
        a = s["agreement"]
        self.db.execute("INSERT INTO stacks VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                        (sid, s["metric"], s["axis_unit"], s["position_unit"], s["frames"],
                         a["textured"], a["both"], a["agree"]))
        rows = []
        for g in s["regions"]:
            fit = g.get("blur_fit") or {}
            rows.append((sid, g["row"], g["col"], g["x"], g["y"], g["w"], g["h"], g["status"],
                         g["status_reason"], g["peak_frame"], g["peak_position"],
                         g["peak_dioptres"], g["at_end"], g["blur_peak_frame"],
                         fit.get("position"), fit.get("slope_px_per_unit"), fit.get("rms_px"),
                         fit.get("points"), g["agree"], g["in_focus_distance_m"]))
        self.db.executemany(f"INSERT INTO stack_regions VALUES ({','.join('?' * 20)})", rows)

    def counts(self):
        """{status: number of sources}."""
        return dict(self.db.execute("SELECT status, COUNT(*) FROM sources GROUP BY status"))


def open_store(path):
    """The Store at @p path; raises OSError naming the path when it cannot be created."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise OSError(f"cannot create {path}: the folder {folder} does not exist")
    try:
        return Store(path)
    except sqlite3.DatabaseError as e:
        raise OSError(f"cannot open {path} as a results database: {e}; give a new file or "
                      "one infocus-batch wrote") from e
