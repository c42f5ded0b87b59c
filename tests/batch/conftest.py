# SPDX-License-Identifier: MIT
"""Shared pieces of the batch tests: the executables (set by meson), the real photographs,
recordings of the simulated camera, and reading a results database."""
import json
import os
import sqlite3
import subprocess
import sys

import pytest

# The columns two runs of the same sources must agree on: all but the times and the row ids.
SOURCE_COLUMNS = ("path, size, mtime_ns, hash, kind, frames, status, error, infocus_version, "
                  "grid, stack")


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("INFOCUS")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("INFOCUS does not name the infocus executable")
    return path


@pytest.fixture(scope="session")
def batch():
    """The infocus-batch command as an argument list."""
    path = os.environ.get("INFOCUS_BATCH")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("INFOCUS_BATCH does not name the infocus-batch launcher")
    return [path]


@pytest.fixture(scope="session")
def data_dir():
    path = os.environ.get("INFOCUS_DATA_DIR", "")
    if not os.path.isdir(path):
        pytest.skip(f"the real photographs are not at '{path}'")
    return os.path.realpath(path)


def record(cli, directory, frames, size="1280x720", extra=""):
    """A recording of the simulated camera: a tilted plane, so regions differ in blur."""
    spec = f"sim:scene=tilted,size={size},focus=0.6m,noise=0.01,pace=fast{extra}"
    subprocess.run([cli, "record", spec, "--frames", str(frames), "-o", directory], check=True,
                   capture_output=True)
    return directory


@pytest.fixture(scope="session")
def recordings(cli, tmp_path_factory):
    """Six recordings of 24 frames of 1280x720 under one folder, made once for the session."""
    root = tmp_path_factory.mktemp("recordings")
    for i in range(6):
        record(cli, str(root / f"rec{i}"), 24, extra=f",seed={i + 1}")
    return str(root)


def run(args, **kw):
    return subprocess.run(args, capture_output=True, text=True, **kw)


def table(db_path, query, args=()):
    db = sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)
    try:
        return db.execute(query, args).fetchall()
    finally:
        db.close()


def contents(db_path):
    """Everything two identical runs must share, keyed by path rather than row id."""
    paths = dict(table(db_path, "SELECT id, path FROM sources"))
    out = {"sources": sorted(table(db_path, f"SELECT {SOURCE_COLUMNS} FROM sources"))}
    for name in ("frames", "regions", "stacks", "stack_regions"):
        rows = table(db_path, f"SELECT * FROM {name}")
        out[name] = sorted((paths[r[0]],) + tuple(r[1:]) for r in rows)
    return out


def cli_jsonl(cli, source):
    out = run([cli, "analyze", source, "--format", "jsonl"], check=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def python():
    return sys.executable
