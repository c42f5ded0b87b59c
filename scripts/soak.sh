#!/usr/bin/env bash
# Runs `infocus live` for MINUTES (default 60) on a simulated 1080p30 camera with the web view
# and 4 clients, each reading /stream.mjpg and /events the whole time. Every 10 s it samples the
# process's RSS, open descriptors and threads, and the pipeline's frame, dropped and skipped
# counts (/state), into soak.csv; then it plots them (soak.png, gnuplot) and checks, from the
# first sample after the first minute on: RSS within +-2 % of that sample, descriptors and threads
# equal to it, no frame dropped, every client still receiving. RSS, descriptors and threads are
# read 10 times over 0.2 s per sample and the least kept (the max beside it): the analysis starts
# a worker thread per frame and reads the CPU count from /sys, so one more thread, descriptor and
# frame buffer comes and goes within a frame, where a leaked one stays.
#   scripts/soak.sh [MINUTES]
# Environment: INFOCUS (default build/src/cli/infocus), SOAK_OUT (default build/soak-MINUTESmin),
# SOAK_INTERVAL (seconds between samples, default 10), SOAK_SOURCE (default
# sim:size=1920x1080,fps=30), SOAK_HAVE_WEB=false (skip: infocus has no web view).
# Exit 0 when every check holds, 1 when one fails, 2 for bad arguments, 77 without a web view.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
minutes=${1:-60}
if ! [[ $minutes =~ ^[0-9]+$ ]] || [[ $minutes -lt 2 ]]; then
	echo "soak.sh: MINUTES is a whole number of at least 2 (the first minute is not judged), not '$minutes'" >&2
	exit 2
fi
infocus=${INFOCUS:-$here/build/src/cli/infocus}
out=${SOAK_OUT:-$here/build/soak-${minutes}min}
interval=${SOAK_INTERVAL:-10}
source=${SOAK_SOURCE:-sim:size=1920x1080,fps=30}
[[ -x $infocus ]] || { echo "soak.sh: no infocus at $infocus; build it or set INFOCUS" >&2; exit 2; }
if [[ ${SOAK_HAVE_WEB:-true} != true ]]; then
	echo "soak.sh: infocus was built without the web view (meson feature web): skipped" >&2
	exit 77
fi
mkdir -p "$out" || exit 1
csv=$out/soak.csv
png=$out/soak.png
log=$out/infocus.log
seconds=$((minutes * 60))

"$infocus" live "$source" --ui web --listen 127.0.0.1:0 --seconds $((seconds + 60)) \
	>/dev/null 2>"$log" &
pid=$!
sampler=
cleanup() {
	[[ -n $sampler ]] && kill "$sampler" 2>/dev/null
	kill -INT "$pid" 2>/dev/null
}
trap cleanup EXIT
url=
for _ in $(seq 100); do
	url=$(grep -oE 'open http://[^ ]+' "$log" | head -1 | cut -d' ' -f2)
	[[ -n $url ]] && break
	kill -0 "$pid" 2>/dev/null || break
	sleep 0.2
done
if [[ -z $url ]]; then
	echo "soak.sh: infocus printed no URL; its log:" >&2
	cat "$log" >&2
	exit 1
fi
base=${url%/}
echo "soak.sh: $source for $minutes min at $base, samples every $interval s into $csv" >&2

# The four clients and the sampler, in one Python process: one interpreter start, where a start
# per sample would lag the rhythm on a loaded machine.
python3 - "$base" "$pid" "$csv" "$seconds" "$interval" <<'PY' &
import json, os, sys, threading, time, urllib.request
base, pid, path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
seconds, interval = float(sys.argv[4]), float(sys.argv[5])
got = [0] * 8  # parts or events each client received


def client(i, url, marker):
    while True:
        try:
            with urllib.request.urlopen(url, timeout=30) as r:
                for line in r:
                    if line.startswith(marker):
                        got[i] += 1
        except OSError:
            time.sleep(1)


for c in range(4):
    threading.Thread(target=client, args=(2 * c, base + '/stream.mjpg', b'X-Frame:'),
                     daemon=True).start()
    threading.Thread(target=client, args=(2 * c + 1, base + '/events', b'id:'),
                     daemon=True).start()

with open(path, 'w') as out:
    out.write('t_s,rss_kib,fds,threads,frame,dropped,skipped,fps,client_min_parts,'
              'client_min_events,fds_max,threads_max,rss_max_kib\n')
    t0, i, was = time.monotonic(), 0, None
    while i * interval <= seconds:
        time.sleep(max(0.0, t0 + i * interval - time.monotonic()))
        # The process first, then /state (its connection is then no descriptor of the sample).
        reads = []
        for k in range(10):
            status = open('/proc/%d/status' % pid).read().split('\n')
            rss = int(next(l.split()[1] for l in status if l.startswith('VmRSS:')))
            threads = int(next(l.split()[1] for l in status if l.startswith('Threads:')))
            reads.append((len(os.listdir('/proc/%d/fd' % pid)), threads, rss))
            time.sleep(0.02)
        fds, threads = min(r[0] for r in reads), min(r[1] for r in reads)
        fds_max, threads_max = max(r[0] for r in reads), max(r[1] for r in reads)
        rss, rss_max = min(r[2] for r in reads), max(r[2] for r in reads)
        try:
            s = json.loads(urllib.request.urlopen(base + '/state', timeout=5).read())
        except (OSError, ValueError):
            s = {}
        now = list(got)
        parts = events = ''
        if was is not None:
            d = [a - b for a, b in zip(now, was)]
            parts, events = min(d[0::2]), min(d[1::2])
        was = now
        out.write('%d,%d,%d,%d,%s,%s,%s,%.1f,%s,%s,%d,%d,%d\n' % (
            round(i * interval), rss, fds, threads, s.get('frame', ''), s.get('dropped', ''),
            s.get('skipped', ''), s.get('fps', 0.0), parts, events, fds_max, threads_max, rss_max))
        out.flush()
        print('%5d s  RSS %.1f MiB  fds %d (max %d)  threads %d (max %d)  dropped %s  %.1f fps  slowest client: '
              '%s parts, %s events' % (i * interval, rss / 1024, fds, fds_max, threads, threads_max,
                                       s.get('dropped', '?'), s.get('fps', 0.0), parts, events),
              file=sys.stderr, flush=True)
        i += 1
PY
sampler=$!
if ! wait "$sampler"; then
	sampler=
	echo "soak.sh: the sampler failed; the log of infocus:" >&2
	cat "$log" >&2
	exit 1
fi
sampler=
kill -0 "$pid" 2>/dev/null || { echo "soak.sh: infocus ended early; its log:" >&2; cat "$log" >&2; exit 1; }
kill -INT "$pid"
wait "$pid"
rc=$?
trap - EXIT

if command -v gnuplot >/dev/null; then
	gnuplot <<GP 2>&1 | grep -v "^$" >&2
set terminal pngcairo size 1200,900 font ",10"
set output "$png"
set datafile separator ","
set multiplot layout 3,1 title "infocus live $source, web view with 4 clients, $minutes min"
set xlabel "time (s)"
set grid
set key top left
set ylabel "RSS (MiB)"
plot "$csv" using 1:(\$2/1024) skip 1 with linespoints title "RSS"
set ylabel "count"
set key center right
plot "$csv" using 1:3 skip 1 with linespoints title "open descriptors", \
	"" using 1:11 skip 1 with lines dashtype 2 title "descriptors, most in 0.2 s", \
	"" using 1:4 skip 1 with linespoints title "threads", \
	"" using 1:12 skip 1 with lines dashtype 2 title "threads, most in 0.2 s"
set ylabel "frames since start"
set key top left
set y2label "per 10 s, slowest client"
set y2tics
plot "$csv" using 1:6 skip 1 with linespoints title "dropped", \
	"" using 1:7 skip 1 with lines title "skipped (analysis took a newer frame)", \
	"" using 1:9 skip 1 axes x1y2 with lines title "stream parts", \
	"" using 1:10 skip 1 axes x1y2 with lines title "events"
unset multiplot
GP
	[[ -s $png ]] && echo "soak.sh: plot in $png" >&2
else
	echo "soak.sh: gnuplot is missing (scripts/install-deps.sh): no plot, the checks still run" >&2
fi

python3 - "$csv" "$interval" "$rc" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
interval, rc = float(sys.argv[2]), int(sys.argv[3])
judged = [r for r in rows if float(r['t_s']) >= 60]
fails = []


def check(ok, what):
    print(('ok    ' if ok else 'FAIL  ') + what)
    if not ok:
        fails.append(what)


if not judged:
    sys.exit('soak.sh: no sample after the first minute')
ref = judged[0]
ref_rss = int(ref['rss_kib'])
rss = [int(r['rss_kib']) for r in judged]
dev = max(abs(x - ref_rss) / ref_rss for x in rss)
check(dev <= 0.02, 'RSS after the first minute: %.1f to %.1f MiB, at most %.2f %% from %.1f MiB '
      'at %s s (<= 2 %%)' % (min(rss) / 1024, max(rss) / 1024, 100 * dev, ref_rss / 1024,
                             ref['t_s']))
for key, name in (('fds', 'open descriptors'), ('threads', 'threads')):
    vals = sorted(set(int(r[key]) for r in judged))
    most = max(int(r[key + '_max']) for r in judged)
    check(len(vals) == 1, '%s after the first minute: %s (constant; up to %d for a moment)' %
          (name, vals, most))
dropped = [int(r['dropped']) if r['dropped'] else -1 for r in rows]
check(all(d == 0 for d in dropped), 'frames dropped: %s at the end, 0 in every sample' %
      dropped[-1])
parts = [int(r['client_min_parts'] or 0) for r in judged]
events = [int(r['client_min_events'] or 0) for r in judged]
check(min(parts) > 0 and min(events) > 0,
      'every client received in every interval: slowest stream client %d to %d parts, slowest '
      'events client %d to %d events per %.0f s' % (min(parts), max(parts), min(events),
                                                    max(events), interval))
last = rows[-1]
print('      %s frames analysed in %s s (%.1f fps), skipped %s' % (
    last['frame'], last['t_s'], int(last['frame'] or 0) / max(1.0, float(last['t_s'])),
    last['skipped']))
check(rc == 0, 'infocus exits 0 on SIGINT (%d)' % rc)
print('%d failure(s)' % len(fails))
sys.exit(1 if fails else 0)
PY
