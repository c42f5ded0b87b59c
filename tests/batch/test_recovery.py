# SPDX-License-Identifier: MIT
"""Nothing lost: a worker of a real dask-scheduler/dask-worker cluster killed mid-task, the
client killed mid-run and rerun, and damaged sources among good ones."""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import pytest

from conftest import contents, run, table

GRID = 16 * 9
FRAMES = 24  # of each recording of the session fixture


def _wait_for(what, predicate, timeout=60.0, proc=None):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        if proc is not None and proc.poll() is not None:
            out, err = proc.communicate()
            pytest.fail(f"{what}: the batch ended first (exit {proc.returncode}): {err}")
        time.sleep(0.05)
    pytest.fail(f"{what}: not within {timeout} s")


@pytest.fixture(scope="module")
def reference(batch, recordings, tmp_path_factory):
    """The one-process run of the recordings: a local cluster of one worker."""
    db = str(tmp_path_factory.mktemp("ref") / "one.sqlite")
    r = run(batch + [recordings, "-o", db, "--workers", "1", "--quiet"])
    assert r.returncode == 0, r.stderr
    return db


def _complete(db, n):
    assert table(db, "SELECT COUNT(*), SUM(status = 'done') FROM sources") == [(n, n)]
    per = table(db, "SELECT s.frames, COUNT(DISTINCT f.frame), MIN(f.frame), MAX(f.frame), "
                "COUNT(*) FROM sources s JOIN frames f ON f.source = s.id GROUP BY s.id")
    assert per == [(FRAMES, FRAMES, 0, FRAMES - 1, FRAMES)] * n  # no gap, no duplicate
    per = table(db, "SELECT COUNT(*), COUNT(DISTINCT frame || ',' || row || ',' || col) "
                "FROM regions GROUP BY source")
    assert per == [(FRAMES * GRID, FRAMES * GRID)] * n


class Cluster:
    """dask-scheduler and two dask-worker processes on 127.0.0.1, free ports chosen by them."""

    def __init__(self, env):
        self.dir = tempfile.mkdtemp(prefix="infocus-dask-")
        self.file = os.path.join(self.dir, "scheduler.json")
        py = sys.executable  # the Python the package was built for, with Debian's Dask
        common = dict(env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.scheduler = subprocess.Popen(
            [py, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
             "--dashboard-address", "127.0.0.1:0", "--scheduler-file", self.file], **common)
        _wait_for("the scheduler's file", lambda: os.path.exists(self.file), 60)
        self.workers = [subprocess.Popen(
            [py, "-m", "distributed.cli.dask_worker", "--scheduler-file", self.file,
             "--host", "127.0.0.1", "--nworkers", "1", "--nthreads", "1", "--no-nanny",
             "--no-dashboard"], **common) for _ in range(2)]
        from distributed import Client
        self.client = Client(scheduler_file=self.file, timeout="30s")
        self.client.wait_for_workers(2, timeout=60)
        self.address = self.client.scheduler.address

    def pid_of(self, address):
        return self.client.run(os.getpid, workers=[address])[address]

    def close(self):
        self.client.close()
        for p in self.workers + [self.scheduler]:
            if p.poll() is None:
                p.terminate()
        for p in self.workers + [self.scheduler]:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        shutil.rmtree(self.dir, ignore_errors=True)


def test_a_killed_worker_loses_nothing(batch, recordings, reference, tmp_path):
    cluster = Cluster(dict(os.environ))
    try:
        db = str(tmp_path / "cluster.sqlite")
        # Three tasks a source: 18 analysis tasks of 8 frames over two workers.
        proc = subprocess.Popen(batch + [recordings, "-o", db, "--scheduler", cluster.address,
                                         "--jobs-per-source", "3", "--quiet"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        victim = {}

        def executing(dask_worker):
            return [str(ts.key) for ts in dask_worker.state.executing]

        def busy():
            # A worker running an analysis task (not one of the first, counting, tasks).
            for addr, keys in cluster.client.run(executing).items():
                if any(k.startswith("analyze_range") for k in keys):
                    victim["addr"] = addr
                    return True
            return False

        _wait_for("a worker busy with an analysis task", busy, 120, proc)
        pid = cluster.pid_of(victim["addr"])
        assert pid in (w.pid for w in cluster.workers)
        os.kill(pid, signal.SIGKILL)
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err
        assert len(cluster.client.scheduler_info()["workers"]) == 1  # it did die
        _complete(db, 6)
        assert contents(db) == contents(reference)
    finally:
        cluster.close()


def test_a_killed_client_resumes(batch, recordings, reference, tmp_path):
    db = str(tmp_path / "resume.sqlite")
    cmd = batch + [recordings, "-o", db, "--workers", "1", "--quiet"]
    # Its own session: the client and the local cluster's worker are killed together.
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)

    def some_done():
        if not os.path.exists(db):
            return False
        try:
            return table(db, "SELECT COUNT(*) FROM sources WHERE status = 'done'")[0][0] >= 2
        except Exception:  # noqa: BLE001  (the database is being created)
            return False

    _wait_for("two sources written", some_done, 120, proc)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    before = dict(table(db, "SELECT path, finished FROM sources WHERE status = 'done'"))
    assert 2 <= len(before) < 6
    r = run(cmd)
    assert r.returncode == 0, r.stderr
    assert f"{len(before)} source(s) already complete, skipped" in r.stderr
    after = dict(table(db, "SELECT path, finished FROM sources"))
    for path, finished in before.items():
        assert after[path] == finished  # not redone
    _complete(db, 6)
    assert contents(db) == contents(reference)


def test_damaged_sources_fail_and_the_rest_complete(cli, batch, recordings, tmp_path):
    root = tmp_path / "mixed"
    root.mkdir()
    for i in range(2):
        shutil.copytree(os.path.join(recordings, f"rec{i}"), root / f"good{i}")
    # One frame's pixels changed after recording: its payload CRC no longer matches.
    bad = root / "bad-crc"
    shutil.copytree(os.path.join(recordings, "rec2"), bad)
    with open(bad / "frames.bin", "r+b") as f:
        f.seek(128 + 1000)
        byte = f.read(1)
        f.seek(128 + 1000)
        f.write(bytes([byte[0] ^ 0xFF]))
    # A header that is not JSON.
    broken = root / "bad-header"
    shutil.copytree(os.path.join(recordings, "rec3"), broken)
    (broken / "header.json").write_text("{ not json")
    db = str(tmp_path / "mixed.sqlite")
    r = run(batch + [str(root), "-o", db, "--workers", "2", "--quiet"])
    assert r.returncode == 1, r.stderr
    assert "2 of 4 source(s) failed" in r.stderr
    rows = {os.path.basename(p): (s, e) for p, s, e in
            table(db, "SELECT path, status, error FROM sources")}
    assert rows["good0"] == ("done", None) and rows["good1"] == ("done", None)
    for name in ("bad-crc", "bad-header"):
        status, error = rows[name]
        assert status == "failed"
        # The library's message, as `infocus analyze` prints it.
        said = run([cli, "analyze", str(root / name), "--format", "csv"]).stderr
        message = re.search(r"infocus analyze: (?:skipped a damaged frame: )?(.*)", said)[1]
        assert message in error, (error, said)
        assert table(db, "SELECT COUNT(*) FROM frames f JOIN sources s ON s.id = f.source "
                     "WHERE s.path = ?", (str(root / name),)) == [(0,)]
    _complete_sources = table(db, "SELECT COUNT(*) FROM regions")[0][0]
    assert _complete_sources == 2 * FRAMES * GRID
