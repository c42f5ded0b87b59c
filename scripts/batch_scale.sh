#!/usr/bin/env bash
# Measures infocus-batch's scaling (docs/batch.md): 40 recordings of 1920x1080 from the simulated
# camera, analysed by a local cluster of 1 and of 2 worker processes, and the scheduler's own
# cost per task from empty tasks. Prints the numbers; writes only under the scratch folder.
# Usage: scripts/batch_scale.sh [BUILD_DIR] [FRAMES_PER_RECORDING] [SCRATCH]
#   defaults: build, 10, a new folder under ${TMPDIR:-/tmp} (removed at the end)
set -euo pipefail

build=${1:-build}
frames=${2:-10}
scratch=${3:-}
sources=40
infocus="$build/src/cli/infocus"
batch="$build/src/py/infocus-batch"
for f in "$infocus" "$batch"; do
	[[ -x $f ]] || { echo "batch_scale: $f is missing; build with -Dpython=enabled" >&2; exit 2; }
done
python=$(sed -n '1s/^#!//p' "$batch")
if [[ -z $scratch ]]; then
	scratch=$(mktemp -d "${TMPDIR:-/tmp}/infocus-scale.XXXXXX")
	trap 'rm -rf "$scratch"' EXIT
fi
mkdir -p "$scratch/rec"

echo "batch_scale: recording $sources x $frames frames of 1920x1080 into $scratch/rec" >&2
for i in $(seq 1 "$sources"); do
	d="$scratch/rec/r$i"
	[[ -e $d/header.json ]] && continue
	"$infocus" record "sim:scene=tilted,size=1920x1080,focus=0.6m,noise=0.01,seed=$i,pace=fast" \
		--frames "$frames" -o "$d" >/dev/null
done
echo "recordings: $(du -sb "$scratch/rec" | cut -f1) bytes"

declare -A wall
for n in 1 2; do
	rm -f "$scratch/w$n.sqlite"*
	# Drop nothing from the page cache: both runs read the recordings from memory.
	start=$(date +%s.%N)
	"$batch" "$scratch/rec" -o "$scratch/w$n.sqlite" --workers "$n" --quiet
	end=$(date +%s.%N)
	wall[$n]=$(echo "$end - $start" | bc -l)
	printf 'workers %d: %.2f s, %.1f frames/s; ' "$n" "${wall[$n]}" \
		"$(echo "$sources * $frames / ${wall[$n]}" | bc -l)"
	# The tasks' own time on the workers, from the database: the rest is start-up, scheduling
	# and the client's writing.
	PYTHONPATH="$build/src/py" "$python" -c '
import sqlite3, sys
n, s = sqlite3.connect(sys.argv[1]).execute(
    "SELECT COUNT(*), SUM(worker_seconds) FROM sources WHERE status = '"'"'done'"'"'").fetchone()
print(f"{n} tasks of {s / n:.3f} s on a worker")' "$scratch/w$n.sqlite"
done
printf 'speed-up 2 workers / 1: %.2fx\n' "$(echo "${wall[1]} / ${wall[2]}" | bc -l)"

# The cluster's start-up, and its cost per task: empty tasks through the same client path. A
# file, not stdin: the local cluster's worker processes import the main module.
cat >"$scratch/overhead.py" <<'PY'
import logging, time
from distributed import Client, LocalCluster

if __name__ == "__main__":
    t0 = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      silence_logs=logging.ERROR, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        print(f"local cluster of 2 workers: {time.perf_counter() - t0:.2f} s to start")
        for n in (200, 2000):
            t = time.perf_counter()
            client.gather([client.submit(int, i, pure=False) for i in range(n)])
            dt = time.perf_counter() - t
            print(f"{n} empty tasks: {dt:.2f} s, {dt / n * 1e3:.2f} ms a task")
PY
"$python" "$scratch/overhead.py"

# The client's cost a frame: writing one recording's rows (as analyze gives them) in one
# transaction, the work that does not spread over workers.
"$infocus" analyze "$scratch/rec/r1" --format jsonl >"$scratch/r1.jsonl"
PYTHONPATH="$build/src/py" "$python" - "$scratch" <<'PY'
import json, os, sys, time
from infocus.batch.store import Store
scratch = sys.argv[1]
records = [json.loads(line) for line in open(os.path.join(scratch, "r1.jsonl"))]
db = os.path.join(scratch, "write.sqlite")
for suffix in ("", "-wal", "-shm"):
    if os.path.exists(db + suffix):
        os.remove(db + suffix)
store = Store(db)
store.queue([(f"/r{i}", "recording", 0, 0) for i in range(20)])
t = time.perf_counter()
for i in range(20):
    store.complete(f"/r{i}", records, "0", "x", "16x9")
dt = (time.perf_counter() - t) / (20 * len(records))
print(f"client: {dt * 1e3:.3f} ms to write a frame of {len(records[0]['regions'])} regions")
PY
