# SPDX-License-Identifier: MIT
"""The tasks the Dask workers run. Each takes plain values and returns plain values (no infocus
object crosses the network), and returns a failure of the source as a message rather than
raising: a task that raises is a bug, a source that cannot be read is a result."""
import ctypes
import json
import os
import time
import warnings

from .sources import content_hash

_malloc_tuned = False


def _tune_malloc():
    """Undoes, in this worker process, what MALLOC_TRIM_THRESHOLD_ does to glibc: Dask's nanny
    sets it for its workers, and any value fixes the mmap threshold at 128 kB, so that every
    frame buffer (2 MB at 1080p) is mapped, faulted in and unmapped again: measured 3x slower
    analysis and 8x slower hashing. The thresholds glibc's own adaptation reaches are restored."""
    global _malloc_tuned
    if _malloc_tuned or "MALLOC_TRIM_THRESHOLD_" not in os.environ:
        return
    _malloc_tuned = True
    try:
        libc = ctypes.CDLL(None)
        m_trim_threshold, m_mmap_threshold = -1, -3  # malloc.h
        libc.mallopt(m_mmap_threshold, 32 << 20)
        libc.mallopt(m_trim_threshold, 64 << 20)
    except (OSError, AttributeError):  # not glibc: nothing to undo
        pass


def _library():
    _tune_malloc()
    # Imported on the worker, where the module may be missing: the message says what to do.
    try:
        import infocus
    except ImportError as e:
        raise ImportError(f"the worker cannot import infocus ({e}); install the infocus package "
                          "for the Python that runs dask-worker") from e
    return infocus


def _threads():
    """Threads for one frame's blur. Each worker thread is already one unit of the cluster's
    parallelism, and Dask's nanny says so to the libraries its tasks call with OMP_NUM_THREADS
    (1); a worker started without a nanny leaves it unset, and the frame takes every core."""
    try:
        return max(0, int(os.environ.get("OMP_NUM_THREADS", "0")))
    except ValueError:
        return 0


def _spec(path, start):
    return path if start == 0 else f"{path},start={start}"


def count_frames(path):
    """The frames the source at @p path holds (None when it does not say), or its error."""
    infocus = _library()
    try:
        with infocus.open(path) as src:
            return {"frames": src.info.get("frame_count"), "error": None}
    except Exception as e:  # noqa: BLE001  (any failure of the library is the source's)
        return {"frames": None, "error": str(e)}


def hash_files(files, root):
    """The content hash of a source (sources.content_hash), or its error."""
    _tune_malloc()
    try:
        return {"hash": content_hash(files, root), "error": None}
    except OSError as e:
        return {"hash": None, "error": f"cannot read {e.filename}: {e.strerror}"}


def analyze_range(path, start, count, grid, files=None, root=None):
    """Measures frames start .. start+count-1 (count 0: to the end) of the source at @p path as
    `infocus analyze` does, over a (cols, rows) grid. Returns the frames as the JSONL records
    analyze writes (parsed), with the source's hash when @p files are given (the first range)."""
    infocus = _library()
    t0 = time.perf_counter()
    out = {"start": start, "records": [], "error": None, "info": None, "hash": None,
           "version": infocus.__version__}
    if files is not None:
        h = hash_files(files, root)
        out["hash"], out["error"] = h["hash"], h["error"]
        if out["error"]:
            return out
    damaged = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            threads = _threads()
            with infocus.open(_spec(path, start)) as src:
                out["info"] = {k: v for k, v in src.info.items()
                               if isinstance(v, (str, int, float, type(None)))}
                for frame in src:
                    # The record analyze writes, read back exactly (shortest round-trip text).
                    rec = json.loads(
                        infocus.analyze(frame, grid=grid, threads=threads).to_json())
                    # A source opened at start=N counts its frames from 0 again.
                    rec["frame"] += start
                    out["records"].append(rec)
                    if count and len(out["records"]) >= count:
                        break
                errors = src.stats.get("errors", 0)
            damaged = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
        if damaged or errors:
            n = max(len(damaged), errors)
            first = damaged[0] if damaged else "the source reported a damaged frame"
            first = first.removeprefix("skipped a damaged frame: ")
            out["error"] = (f"{n} damaged frame(s), the first: {first}; `infocus analyze` "
                            "measures the intact frames of a damaged source")
    except Exception as e:  # noqa: BLE001
        out["error"] = str(e)
    out["seconds"] = time.perf_counter() - t0
    return out


def analyze_stack(path, grid, stack_grid, files, root):
    """analyze_range over the whole source, and `infocus stack` on it: the stack's regions (peak
    frame, blur vertex, agreement) without their curves."""
    out = analyze_range(path, 0, 0, grid, files, root)
    if out["error"]:
        return out
    infocus = _library()
    t0 = time.perf_counter()
    try:
        s = infocus.stack(path, grid=stack_grid, maps=False, threads=1)
        keep = ("source", "metric", "axis_unit", "position_unit", "agreement", "regions")
        doc = {k: s[k] for k in keep}
        doc["frames"] = len(s["frames"])
        for r in doc["regions"]:
            r.pop("curve", None)
        out["stack"] = json.dumps(doc)
    except Exception as e:  # noqa: BLE001
        out["error"] = f"stack: {e}"
    out["seconds"] += time.perf_counter() - t0
    return out
