# SPDX-License-Identifier: MIT
"""The batch client: finds the sources, skips those already complete, hands the rest to a Dask
cluster as tasks and writes each source to the database when all its tasks are in."""
import argparse
import logging
import math
import os
import re
import sys
import time

from . import work
from .export import write_export
from .sources import DiscoveryError, discover
from .store import open_store

PROG = "infocus-batch"
EXIT_USAGE = 2


def _grid(text):
    m = re.fullmatch(r"(\d+)x(\d+)", text)
    if not m or not (1 <= int(m[1]) <= 256 and 1 <= int(m[2]) <= 256):
        raise argparse.ArgumentTypeError(
            f"{text}: give columns x rows from 1x1 to 256x256, e.g. 16x9")
    return int(m[1]), int(m[2])


def _positive(text):
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"{text}: give a whole number of 1 or more")
    return int(text)


def batch_parser():
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Analyses every source under the given paths on a Dask cluster (an embedded "
        "local one by default) into an SQLite database; a rerun resumes. "
        f"`{PROG} export RESULTS.sqlite --format csv|jsonl` writes the rows `infocus analyze` "
        "would.")
    p.add_argument("sources", nargs="+", metavar="SOURCE",
                   help="recording, video, image, image directory or glob, or a folder of them")
    p.add_argument("-o", "--output", required=True, metavar="RESULTS.sqlite",
                   help="the results database (created, or resumed when it exists)")
    p.add_argument("--scheduler", metavar="ADDR",
                   help="an existing Dask scheduler, e.g. tcp://host:8786 (default: a local "
                   "cluster)")
    p.add_argument("--workers", type=_positive, metavar="N",
                   help="worker processes of the local cluster (default: one a core)")
    p.add_argument("--grid", type=_grid, metavar="CxR",
                   help="regions as columns x rows (default: analyze's 16x9; stack's 8x6)")
    p.add_argument("--stack", action="store_true",
                   help="also measure each source as a focus stack, one task a source")
    p.add_argument("--jobs-per-source", type=_positive, default=1, metavar="K",
                   help="split each source into K frame ranges, one task each (default 1)")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    return p


def export_parser():
    p = argparse.ArgumentParser(
        prog=f"{PROG} export",
        description="Writes the rows `infocus analyze --format csv|jsonl` writes, from a results "
        "database: one source gives analyze's bytes, several a leading source column.")
    p.add_argument("database", metavar="RESULTS.sqlite")
    p.add_argument("--format", choices=("csv", "jsonl"), default="jsonl")
    p.add_argument("--source", metavar="PATH", help="only this source")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (default: stdout)")
    return p


def _error(message, code=1):
    print(f"{PROG}: {message}", file=sys.stderr)
    return code


class Progress:
    """A progress line on stderr: sources and frames done, rate, time left. Redrawn in place on
    a terminal; elsewhere a line every 30 s."""

    def __init__(self, total, quiet):
        self.total, self.done, self.failed, self.frames = total, 0, 0, 0
        self.t0 = self.last = time.monotonic()
        self.tty = sys.stderr.isatty()
        self.quiet = quiet

    def add(self, frames, failed):
        self.done += 1
        self.failed += failed
        self.frames += frames
        now = time.monotonic()
        if self.quiet or (not self.tty and now - self.last < 30 and self.done < self.total):
            return
        self.last = now
        elapsed = now - self.t0
        rate = self.frames / elapsed if elapsed > 0 else 0.0
        left = elapsed / self.done * (self.total - self.done)
        bar = "#" * (20 * self.done // max(self.total, 1))
        line = (f"[{bar:<20}] {self.done}/{self.total} sources ({self.failed} failed), "
                f"{self.frames} frames, {rate:.1f} frames/s, {int(left) // 60}:"
                f"{int(left) % 60:02d} left")
        print(("\r" + line + "\033[K") if self.tty else line, end="" if self.tty else "\n",
              file=sys.stderr, flush=True)

    def finish(self):
        if self.tty and not self.quiet and self.done:
            print(file=sys.stderr)


def _ranges(frames, k):
    """[(start, count)] splitting @p frames into at most @p k ranges; the last runs to the end
    (count 0), so that a source longer than it said loses no frame."""
    if not frames or k <= 1:
        return [(0, 0)]
    k = min(k, frames)
    size = math.ceil(frames / k)
    starts = list(range(0, frames, size))
    return [(s, size) for s in starts[:-1]] + [(starts[-1], 0)]


class Pending:
    """The tasks of one source still out, and the parts already in."""

    def __init__(self, source):
        self.source = source
        self.out = 0
        self.parts = []
        self.error = None


def _cluster(args):
    """(client, closer) for --scheduler or a new local cluster."""
    from distributed import Client, LocalCluster
    try:
        import bokeh  # noqa: F401  (the dashboard needs it)
        dashboard = True
    except ImportError:
        dashboard = False
    if args.scheduler:
        client = Client(args.scheduler, timeout="30s")
        try:
            client.wait_for_workers(1, timeout=60)
        except Exception:  # noqa: BLE001  (a TimeoutError of distributed's own making)
            client.close()
            raise RuntimeError(f"no worker joined the scheduler at {args.scheduler} within 60 s;"
                               f" start `dask-worker {args.scheduler}` where the sources are "
                               "readable")
        closers = [client]
    else:
        n = args.workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               silence_logs=logging.ERROR,
                               dashboard_address=":8787" if dashboard else None)
        client = Client(cluster)
        closers = [client, cluster]
    if dashboard and client.dashboard_link:
        print(f"{PROG}: dashboard at {client.dashboard_link}", file=sys.stderr)
    return client, closers


def run_batch(args):
    grid = args.grid or (16, 9)
    stack_grid = args.grid or (8, 6)
    grid_text = f"{grid[0]}x{grid[1]}"
    try:
        sources = discover(args.sources)
    except DiscoveryError as e:
        return _error(str(e), EXIT_USAGE)
    if not sources:
        return _error("no source found under " + " ".join(args.sources) + "; give recordings, "
                      "videos, images or folders of them", EXIT_USAGE)
    try:
        store = open_store(args.output)
    except OSError as e:
        return _error(str(e))

    try:
        client, closers = _cluster(args)
    except (RuntimeError, OSError) as e:
        store.close()
        return _error(str(e))
    try:
        return _schedule(args, client, store, sources, grid, stack_grid, grid_text)
    except KeyboardInterrupt:
        done = store.counts().get("done", 0)
        return _error(f"interrupted; {done} source(s) are complete in {args.output}: run the "
                      "same command again to go on", 130)
    finally:
        for c in closers:
            c.close()
        store.close()


def _schedule(args, client, store, sources, grid, stack_grid, grid_text):
    from distributed import as_completed

    # Skipped: complete with the same options, size and mtime, and (asked of a worker, which
    # reads the storage) the same hash.
    idents, todo, checks = {}, [], {}
    for s in sources:
        try:
            idents[s.path] = s.identity() if not s.error else (None, None)
        except OSError as e:
            s.error = f"cannot read {e.filename}: {e.strerror}; check it exists and is readable"
            idents[s.path] = (None, None)
        prev = store.previous(s.path)
        if (prev and not s.error and prev[:2] == idents[s.path] and prev[3] == grid_text
                and bool(prev[4]) == args.stack):
            checks[s.path] = (client.submit(work.hash_files, s.files, s.root, pure=False), prev[2])
        else:
            todo.append(s)
    skipped = 0
    for s in sources:
        if s.path in checks:
            fut, old = checks[s.path]
            try:
                same = fut.result()["hash"] == old
            except Exception:  # noqa: BLE001  (its worker died: analyse it again)
                same = False
            if same:
                skipped += 1
            else:
                todo.append(s)
    store.queue([(s.path, s.kind, *idents[s.path]) for s in todo])
    if skipped:
        print(f"{PROG}: {skipped} source(s) already complete, skipped", file=sys.stderr)

    progress = Progress(len(todo), args.quiet)
    failed = 0
    pending = {}
    queue = as_completed()

    def finish(p, error=None, digest=None, records=(), version=None, stack=None):
        nonlocal failed
        if error:
            store.fail(p.source.path, error, version)
            failed += 1
        else:
            seconds = sum(q.get("seconds", 0.0) for q in p.parts)
            store.complete(p.source.path, records, digest, version, grid_text, stack, seconds)
        progress.add(len(records), bool(error))

    for s in todo:
        p = pending[s.path] = Pending(s)
        if s.error:
            finish(p, s.error)
        elif args.stack:
            f = client.submit(work.analyze_stack, s.path, grid, stack_grid, s.files, s.root,
                              pure=False)
            f.meta = ("part", s.path)
            p.out = 1
            queue.add(f)
        elif args.jobs_per_source > 1:
            f = client.submit(work.count_frames, s.path, pure=False)
            f.meta = ("count", s.path)
            queue.add(f)
            p.out = 1
        else:
            f = client.submit(work.analyze_range, s.path, 0, 0, grid, s.files, s.root,
                              pure=False)
            f.meta = ("part", s.path)
            p.out = 1
            queue.add(f)

    for f in queue:
        what, path = f.meta
        p = pending[path]
        p.out -= 1
        try:
            r = f.result()
        except Exception as e:  # noqa: BLE001  (a worker that died too often, a lost task)
            r = {"error": f"the task failed on the cluster: {type(e).__name__}: {e}"}
        f.release()
        if what == "count":
            if r["error"]:
                finish(p, r["error"])
                continue
            for start, count in _ranges(r["frames"], args.jobs_per_source):
                # The first range hashes the source's files.
                g = client.submit(work.analyze_range, path, start, count, grid,
                                  p.source.files if start == 0 else None, p.source.root,
                                  pure=False)
                g.meta = ("part", path)
                p.out += 1
                queue.add(g)
            continue
        p.parts.append(r)
        if r.get("error") and not p.error:
            p.error = r["error"]
        if p.out:
            continue
        version = next((q.get("version") for q in p.parts if q.get("version")), None)
        if p.error:
            finish(p, p.error, version=version)
            continue
        p.parts.sort(key=lambda q: q["start"])
        records = [rec for q in p.parts for rec in q["records"]]
        digest = next(q["hash"] for q in p.parts if q["start"] == 0)
        stack = p.parts[0].get("stack")
        if not records:
            finish(p, f"{path} delivered no frame", version=version)
        else:
            finish(p, None, digest, records, version, stack)
        del pending[path]
    progress.finish()
    if failed:
        print(f"{PROG}: {failed} of {len(todo)} source(s) failed; their errors are in "
              f"{args.output} (sources.error)", file=sys.stderr)
        return 1
    return 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "export":
        a = export_parser().parse_args(argv[1:])
        if not os.path.isfile(a.database):
            return _error(f"{a.database} does not exist; give a database infocus-batch wrote",
                          EXIT_USAGE)
        try:
            store = open_store(a.database)
        except OSError as e:
            return _error(str(e))
        try:
            n = write_export(store.db, a.format, a.output, a.source)
        except LookupError as e:
            return _error(str(e), EXIT_USAGE)
        except OSError as e:
            return _error(f"cannot write {a.output}: {e.strerror}")
        finally:
            store.close()
        if n == 0:
            return _error(f"{a.database} holds no complete source")
        return 0
    args = batch_parser().parse_args(argv)
    if args.scheduler and args.workers:
        return _error("--workers sizes the local cluster; with --scheduler the cluster's own "
                      "workers run the tasks: drop one of them", EXIT_USAGE)
    try:
        import distributed  # noqa: F401
    except ImportError as e:
        return _error(f"Dask distributed is not installed ({e}); apt-get install "
                      "python3-distributed")
    return run_batch(args)
