#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The web view under a flood of connections, on loopback only.

`infocus live sim:size=640x360,fps=30 --ui web --listen 127.0.0.1:0` gets RATE new connections a
second (default 1,000) for SECONDS (default 10) from a generator in a child process, a third each
of:
  valid      a whole request (GET /state, /, /app.js, POST /control reset_peak), its answer read
  half-open  a connection that sends nothing, half a request head, or a whole request and then
             never reads; held until the server closes it or 3 s pass
  garbage    random bytes, a request line of junk, an oversized header, a bad method or version
Meanwhile a probe asks GET /state on a fresh connection every 50 ms and times connect to last byte,
and the server's RSS, threads and open descriptors are read from /proc every 0.25 s.

Passes when: the generator opened at least 90 % of RATE x SECONDS connections; every probe got a
200 within 100 ms; the server's threads never exceed those it had before the flood plus 8 (its
pool is fixed; the tolerance is for the pipeline's own short-lived work); its RSS peak stays within
64 MiB of where it started and, 3 s after the flood, within 16 MiB; its descriptors return to
within 8 of the start; the pipeline's `dropped` stays 0; and the process still exits 0 on SIGINT.

usage: test_web_flood.py INFOCUS HAVE_WEB(true|false) [RATE] [SECONDS]
Exits 77 when infocus was built without the web view.
"""
import http.client
import json
import os
import random
import re
import resource
import selectors
import signal
import socket
import subprocess
import sys
import threading
import time

PROBE_LIMIT_S = 0.100
HALF_OPEN_HOLD_S = 3.0
failures = []


def check(ok, what):
    print(('ok    ' if ok else 'FAIL  ') + what, flush=True)
    if not ok:
        failures.append(what)
    return ok


# ---- the generator (a child process, so that its work never delays the probe) ----------------

VALID = [
    b'GET /state HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n',
    b'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n',
    b'GET /app.js HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n',
    b'POST /control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n'
    b'Content-Length: 20\r\nConnection: close\r\n\r\n{"reset_peak": true}',
]


def garbage(rng):
    kind = rng.randrange(5)
    if kind == 0:
        return bytes(rng.randrange(256) for _ in range(rng.randrange(1, 600))) + b'\r\n\r\n'
    if kind == 1:
        return b'GET /' + bytes(rng.randrange(33, 127) for _ in range(200)) + b' HTTP/1.1\r\n\r\n'
    if kind == 2:
        return b'GET /state HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: ' + b'a' * 20000 + b'\r\n\r\n'
    if kind == 3:
        return b'BREW /state HTCPCP/1.0\r\nHost: 127.0.0.1\r\n\r\n'
    return (b'POST /control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n'
            b'Content-Length: 99999999\r\n\r\n{"focus_step":')


def generate(host, port, rate, seconds):
    """Opens RATE connections a second for SECONDS; prints a JSON summary on stdout."""
    rng = random.Random(66)
    sel = selectors.DefaultSelector()
    conns = {}  # socket -> dict(kind, out, deadline, got)
    counts = {'valid': 0, 'half-open': 0, 'garbage': 0}
    stats = {'opened': 0, 'connect_errors': 0, 'answered': 0, 'closed_by_server': 0,
             'reset': 0, 'held_to_end': 0}
    kinds = ['valid', 'half-open', 'garbage']

    def close(s):
        sel.unregister(s)
        conns.pop(s)
        s.close()

    def open_one(i):
        kind = kinds[i % 3]
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.setblocking(False)
        try:
            s.connect_ex((host, port))
        except OSError:
            stats['connect_errors'] += 1
            s.close()
            return
        if kind == 'valid':
            out = VALID[(i // 3) % len(VALID)]
        elif kind == 'garbage':
            out = garbage(rng)
        else:
            h = (i // 3) % 3
            out = [b'', b'GET /state HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-A',
                   VALID[1]][h]
        c = {'kind': kind, 'out': out, 'got': 0, 'read': kind != 'half-open',
             'deadline': time.monotonic() + (HALF_OPEN_HOLD_S if kind == 'half-open' else 5.0)}
        conns[s] = c
        counts[kind] += 1
        stats['opened'] += 1
        sel.register(s, selectors.EVENT_WRITE | selectors.EVENT_READ)

    t0 = time.monotonic()
    i = 0
    end = t0 + seconds
    while True:
        now = time.monotonic()
        # Connections due by now, spread evenly.
        due = min(int((now - t0) * rate), int(rate * seconds))
        while i < due:
            open_one(i)
            i += 1
        if now >= end and not conns:
            break
        if now >= end + HALF_OPEN_HOLD_S + 3:
            break
        for key, ev in sel.select(timeout=0.002):
            s = key.fileobj
            c = conns.get(s)
            if c is None:
                continue
            if ev & selectors.EVENT_WRITE and c['out']:
                try:
                    n = s.send(c['out'])
                    c['out'] = c['out'][n:]
                except BlockingIOError:
                    pass
                except OSError:
                    stats['reset'] += 1
                    close(s)
                    continue
                if not c['out']:
                    sel.modify(s, selectors.EVENT_READ)
            elif ev & selectors.EVENT_WRITE and not c['out']:
                sel.modify(s, selectors.EVENT_READ)
            if ev & selectors.EVENT_READ:
                if not c['read']:
                    # A half-open client never reads; it only notices the server's close.
                    try:
                        data = s.recv(1, socket.MSG_PEEK)
                    except OSError:
                        data = b''
                    if data:
                        # An answer it will never read: stop watching, close at its deadline.
                        sel.unregister(s)
                        c['parked'] = True
                        continue
                    stats['closed_by_server'] += 1
                    close(s)
                    continue
                try:
                    data = s.recv(65536)
                except BlockingIOError:
                    continue
                except OSError:
                    stats['reset'] += 1
                    close(s)
                    continue
                if not data:
                    if c['got']:
                        stats['answered'] += 1
                    else:
                        stats['closed_by_server'] += 1
                    close(s)
                else:
                    c['got'] += len(data)
        now = time.monotonic()
        for s, c in list(conns.items()):
            if now > c['deadline']:
                stats['held_to_end'] += 1
                if c.get('parked'):
                    conns.pop(s)
                    s.close()
                else:
                    close(s)
    stats.update(counts)
    stats['seconds'] = round(time.monotonic() - t0, 2)
    stats['rate'] = round(i / seconds, 1)
    print(json.dumps(stats), flush=True)


# ---- the test ------------------------------------------------------------------------------------

def proc_status(pid):
    """(RSS in KiB, threads, open descriptors) of process PID."""
    rss = threads = 0
    with open('/proc/%d/status' % pid) as f:
        for line in f:
            if line.startswith('VmRSS:'):
                rss = int(line.split()[1])
            elif line.startswith('Threads:'):
                threads = int(line.split()[1])
    return rss, threads, len(os.listdir('/proc/%d/fd' % pid))


def get_state(host, port, timeout=5.0):
    c = http.client.HTTPConnection(host, port, timeout=timeout)
    try:
        c.request('GET', '/state')
        r = c.getresponse()
        body = r.read()
        return r.status, (json.loads(body) if r.status == 200 else None)
    finally:
        c.close()


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == '--generate':
        generate(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]))
        return
    if len(sys.argv) < 3 or sys.argv[2] != 'true':
        print('skipped: infocus was built without the web view (meson feature web, '
              'libcpp-httplib-dev)')
        sys.exit(77)
    infocus = sys.argv[1]
    rate = float(sys.argv[3]) if len(sys.argv) > 3 else 1000.0
    seconds = float(sys.argv[4]) if len(sys.argv) > 4 else 10.0
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = int(rate * HALF_OPEN_HOLD_S) + 1024
    if hard != resource.RLIM_INFINITY and hard < need:
        print('skipped: the generator needs %d descriptors, the hard limit is %d' % (need, hard))
        sys.exit(77)
    resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, need), hard))

    proc = subprocess.Popen(
        [infocus, 'live', 'sim:size=640x360,fps=30', '--ui', 'web', '--listen', '127.0.0.1:0',
         '--seconds', str(int(seconds) + 60)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    url = None
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline and url is None:
        line = proc.stderr.readline()
        if not line:
            break
        m = re.search(r'open (http://\S+)', line)
        url = m.group(1) if m else None
    if not url:
        proc.kill()
        sys.exit('FAIL  no URL on stderr')
    threading.Thread(target=lambda: [None for _ in proc.stderr], daemon=True).start()
    m = re.match(r'http://([^:/]+):(\d+)/', url)
    host, port = m.group(1), int(m.group(2))

    state = None
    for _ in range(200):
        status, state = get_state(host, port)
        if status == 200:
            break
        time.sleep(0.05)
    check(state is not None, 'the server answers /state before the flood')
    time.sleep(1.0)  # the pipeline's threads and buffers settle
    base = proc_status(proc.pid)
    print('      before: RSS %.1f MiB, %d threads, %d fds' % (base[0] / 1024, base[1], base[2]))

    samples, probes, stop = [], [], threading.Event()

    def sampler():
        while not stop.is_set():
            samples.append(proc_status(proc.pid))
            stop.wait(0.25)

    def prober():
        while not stop.is_set():
            t = time.monotonic()
            try:
                status, _ = get_state(host, port, timeout=2.0)
            except OSError as e:
                status = str(e)
            probes.append((status, time.monotonic() - t))
            stop.wait(0.05)

    threads = [threading.Thread(target=sampler), threading.Thread(target=prober)]
    for t in threads:
        t.start()
    gen = subprocess.run([sys.executable, __file__, '--generate', host, str(port), str(rate),
                          str(seconds)], capture_output=True, text=True,
                         timeout=seconds + HALF_OPEN_HOLD_S + 60)
    stop.set()
    for t in threads:
        t.join()
    try:
        g = json.loads(gen.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        g = {}
        print(gen.stdout, gen.stderr)
    print('      generator: %s' % json.dumps(g))
    check(g.get('opened', 0) >= 0.9 * rate * seconds,
          'the generator opened %d connections in %.0f s (>= 90 %% of %d)' %
          (g.get('opened', 0), seconds, rate * seconds))

    bad = [p for p in probes if p[0] != 200]
    slow = sorted(p[1] for p in probes)
    worst = slow[-1] if slow else 99.0
    p50 = slow[len(slow) // 2] if slow else 99.0
    check(probes and not bad, '/state probes during the flood: %d, all 200 (not: %s)' %
          (len(probes), bad[:5]))
    p90 = slow[int(len(slow) * 0.9)] if slow else 99.0
    check(worst <= PROBE_LIMIT_S, '/state during the flood: median %.1f ms, 90th percentile '
          '%.1f ms, worst %.1f ms (<= %.0f ms)' % (p50 * 1e3, p90 * 1e3, worst * 1e3,
                                                   PROBE_LIMIT_S * 1e3))

    peak_rss = max(s[0] for s in samples)
    peak_threads = max(s[1] for s in samples)
    peak_fds = max(s[2] for s in samples)
    print('      during: RSS peak %.1f MiB, threads peak %d, fds peak %d' %
          (peak_rss / 1024, peak_threads, peak_fds))
    check(peak_threads <= base[1] + 8, 'threads during the flood: at most %d (start %d, +8)' %
          (peak_threads, base[1]))
    check(peak_rss <= base[0] + 64 * 1024, 'RSS peak during the flood: %.1f MiB (start %.1f, '
          '+64 MiB)' % (peak_rss / 1024, base[0] / 1024))
    time.sleep(3.0)
    after = proc_status(proc.pid)
    print('      3 s after: RSS %.1f MiB, %d threads, %d fds' %
          (after[0] / 1024, after[1], after[2]))
    check(after[0] <= base[0] + 16 * 1024, 'RSS 3 s after the flood: %.1f MiB (start %.1f, '
          '+16 MiB)' % (after[0] / 1024, base[0] / 1024))
    check(abs(after[2] - base[2]) <= 8, 'descriptors 3 s after the flood: %d (start %d, +-8)' %
          (after[2], base[2]))
    status, state = get_state(host, port)
    check(status == 200 and state['dropped'] == 0,
          'the pipeline dropped %s frames (0); %s analysed, skipped %s' %
          ((state or {}).get('dropped'), (state or {}).get('frame'), (state or {}).get('skipped')))
    proc.send_signal(signal.SIGINT)
    try:
        rc = proc.wait(15)
    except subprocess.TimeoutExpired:
        proc.kill()
        rc = None
    check(rc == 0, 'SIGINT after the flood: exit 0 (%s)' % rc)
    print('%d failure(s)' % len(failures))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
