#!/usr/bin/env python3
"""The web view as a person uses it: `infocus live` on the simulated camera with `--ui web`,
opened in a real headless Chromium at phone (360x640) and desktop (1280x800) sizes.

The server wants a token (--token), so every request of the page must carry the one in its URL.
Checks, at each size: the page loads with no console error (SEVERE log empty); the preview canvas
shows a picture (the standard deviation of its pixels above 5 grey levels); the meter's score
changes while the lens moves (one click of a focus button gives the step, two more move the
lens by three of them within 1e-6); a tap on the preview places the magnifier at the tapped frame
coordinates (within 4 frame pixels, a little over one CSS pixel on the phone) and the inset shows
its crop. Then, with the sound on (muted), Autofocus brings the lens to the sim's 1 m, i.e.
1.0 dpt within 0.02 dpt.
Screenshots (phone and desktop, before and after autofocus) are saved as PNGs in the directory
printed at the end.

Usage: test_web_browser.py --infocus PATH [--out DIR] [--page-dir DIR]
  --page-dir DIR  serve index.html, app.js and style.css from DIR in front of the server and pass
                  every other path on to it, to try page edits without rebuilding the binary.
Exits 77 when chromium, chromedriver or selenium are missing, or infocus has no web face.
"""
import argparse
import http.client
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

SOURCE = "sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m"
LENS_ARGS = ["--focal", "16mm", "-N", "1.4", "--pixel-pitch", "3um"]
SIM_FOCUS_DPT = 1.0  # the sim's subject at 1 m
AF_TOLERANCE_DPT = 0.02
TAP_TOLERANCE_PX = 4
TOKEN = "browser-test-token"


def skip(reason):
    print("SKIP: " + reason)
    sys.exit(77)


try:
    from selenium import webdriver
    from selenium.common.exceptions import WebDriverException
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
except ImportError:
    # Debian's python3-selenium lives beside the system's python3; another python3 first on the
    # PATH (a virtualenv) does not see it.
    system = "/usr/bin/python3"
    if os.path.exists(system) and os.path.realpath(sys.executable) != os.path.realpath(system) \
            and not os.environ.get("INFOCUS_TEST_REEXEC"):
        os.environ["INFOCUS_TEST_REEXEC"] = "1"
        os.execv(system, [system] + sys.argv)
    skip("python3-selenium is missing")

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"

failures = []
passes = 0


def check(ok, what):
    global passes
    if ok:
        passes += 1
    else:
        failures.append(what)
        print("FAIL: " + what, flush=True)


def wait_until(seconds, probe, step=0.25):
    """Polls probe until it returns something true; returns that, or None on time-out."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        got = probe()
        if got:
            return got
        time.sleep(step)
    return None


class Server:
    """`infocus live --ui web` on the sim, its URL read from stderr."""

    def __init__(self, infocus):
        # A token even on loopback: every request the page makes must carry it, or gets 401.
        cmd = [infocus, "live", SOURCE, "--ui", "web", "--listen", "127.0.0.1:0",
               "--token", TOKEN] + LENS_ARGS
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True)
        self.stderr = []
        self.url_found = threading.Event()
        self.url = None
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stderr:
            self.stderr.append(line)
            m = re.search(r"open (https?://\S+)", line)
            if m and not self.url:
                self.url = m.group(1)
                self.url_found.set()

    def wait_url(self, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end and not self.url_found.is_set():
            if self.proc.poll() is not None:
                time.sleep(0.2)  # let the reader take the last lines
                return None
            time.sleep(0.1)
        return self.url

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        return self.proc.returncode


class Api:
    """The server's JSON endpoints, with the token of the printed URL."""

    def __init__(self, url):
        u = urllib.parse.urlsplit(url)
        self.base = f"{u.scheme}://{u.netloc}"
        self.token = urllib.parse.parse_qs(u.query).get("token", [None])[0]

    def path(self, p):
        return self.base + p + (f"?token={self.token}" if self.token else "")

    def state(self):
        try:
            with urllib.request.urlopen(self.path("/state"), timeout=5) as r:
                return json.load(r)
        except (urllib.error.URLError, OSError, ValueError):
            return None


def page_proxy(page_dir, upstream):
    """Serves the page files from page_dir and streams every other path from upstream."""
    up = urllib.parse.urlsplit(upstream)
    files = {"/": ("index.html", "text/html"), "/app.js": ("app.js", "text/javascript"),
             "/style.css": ("style.css", "text/css")}

    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args):
            pass

        def do_GET(self):
            path = urllib.parse.urlsplit(self.path).path
            if path in files:
                name, ctype = files[path]
                with open(os.path.join(page_dir, name), "rb") as f:
                    body = f.read()
                self.send_response(200)
                self.send_header("Content-Type", ctype + "; charset=utf-8")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)
                return
            n = int(self.headers.get("Content-Length") or 0)
            body = self.rfile.read(n) if n else None
            conn = http.client.HTTPConnection(up.hostname, up.port, timeout=600)
            headers = {k: v for k, v in self.headers.items()
                       if k.lower() in ("content-type", "authorization")}
            try:
                conn.request(self.command, self.path, body, headers)
                r = conn.getresponse()
            except OSError:  # the server is gone: say so as it would, without a traceback
                self.send_error(502)
                return
            self.send_response(r.status)
            for k, v in r.getheaders():
                if k.lower() not in ("connection", "transfer-encoding", "keep-alive"):
                    self.send_header(k, v)
            self.send_header("Connection", "close")
            self.end_headers()
            try:  # streams (MJPEG, events) pass through as they come
                while chunk := r.read1(65536):
                    self.wfile.write(chunk)
                    self.wfile.flush()
            except OSError:
                pass

        do_POST = do_GET

    ThreadingHTTPServer.daemon_threads = True
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    return f"http://127.0.0.1:{httpd.server_address[1]}/"


def browser(width, height, phone):
    o = webdriver.ChromeOptions()
    o.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              "--mute-audio"):
        o.add_argument(a)
    # Device metrics fix the viewport itself (a window size would include the browser's frame);
    # the phone also gets a phone's pixel ratio and touch.
    o.add_experimental_option("mobileEmulation", {"deviceMetrics": {
        "width": width, "height": height, "pixelRatio": 2 if phone else 1,
        "mobile": phone, "touch": phone}})
    o.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=o)


# The preview's spread of grey levels over its pixels (0 for a blank canvas).
PIXEL_SPREAD_JS = """
const c = document.getElementById('preview');
if (!c || c.width < 2) return 0;
const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
let n = 0, s = 0, s2 = 0;
for (let i = 0; i < d.length; i += 4 * 7) { const v = d[i + 1]; n++; s += v; s2 += v * v; }
const m = s / n;
return Math.sqrt(Math.max(0, s2 / n - m * m));
"""


class Session:
    """One browser at one size, with its console errors collected as they come."""

    def __init__(self, name, width, height, phone, url):
        self.name = name
        self.d = browser(width, height, phone)
        self.severe = []
        self.d.get(url)

    def drain_log(self):
        for e in self.d.get_log("browser"):
            if e.get("level") == "SEVERE":
                self.severe.append(e.get("message", ""))

    def text(self, id_):
        return self.d.find_element(By.ID, id_).text

    def shot(self, out, suffix):
        path = os.path.join(out, f"{self.name}-{suffix}.png")
        self.d.save_screenshot(path)
        return path


def check_page(s, api, step_button, tap_at):
    name = s.name
    spread = wait_until(20, lambda: (v := s.d.execute_script(PIXEL_SPREAD_JS)) > 5 and v)
    check(spread, f"{name}: the preview canvas shows no picture (pixel spread ≤ 5)")
    if spread:
        print(f"{name}: preview pixel spread {spread:.1f} grey levels")

    # The meter's number while the lens moves: one click gives the step, two more must add two
    # more of the same (a continuous control reports no step of its own).
    before = api.state()
    v0 = before["lens_position"]["value"]
    scores = {s.text("score")}
    button = s.d.find_element(By.ID, step_button)
    button.click()
    first = wait_until(15, lambda: (st := api.state()) and st["lens_position"]["value"] != v0
                       and st)
    check(first, f"{name}: {step_button} did not move the lens from {v0}")
    after = first
    if first:
        step = first["lens_position"]["value"] - v0
        for _ in range(2):
            time.sleep(0.5)
            scores.add(s.text("score"))
            button.click()
        after = wait_until(15, lambda: (st := api.state()) and abs(
            st["lens_position"]["value"] - v0 - 3 * step) < 1e-6 and st)
        check(after, f"{name}: three clicks of {step_button} did not move the lens 3 × {step:.4g} "
              f"from {v0} (it is at {api.state()['lens_position']['value']})")
    for _ in range(8):  # the sim re-renders slowly away from focus: let a few frames through
        time.sleep(0.5)
        scores.add(s.text("score"))
    check(len(scores) >= 2, f"{name}: the meter's score did not change while the lens moved "
          f"({sorted(scores)})")
    moved_to = after and after["lens_position"]["value"]
    print(f"{name}: lens {v0} → {moved_to}, scores seen {sorted(scores)[:6]}")

    # A tap on the preview: the magnifier goes there, in frame pixels, and the inset shows.
    canvas = s.d.find_element(By.ID, "preview")
    w, h = s.d.execute_script("const r = arguments[0].getBoundingClientRect();"
                              "return [r.width, r.height];", canvas)
    fw, fh = before["width"], before["height"]
    dx, dy = round(w * tap_at[0]), round(h * tap_at[1])
    ActionChains(s.d).move_to_element_with_offset(canvas, dx - round(w / 2),
                                                  dy - round(h / 2)).click().perform()
    want = (dx / w * fw, dy / h * fh)
    got = wait_until(10, lambda: (st := api.state()) and st.get("magnifier"))
    check(got and abs(got["x"] - want[0]) <= TAP_TOLERANCE_PX
          and abs(got["y"] - want[1]) <= TAP_TOLERANCE_PX,
          f"{name}: tap at frame ({want[0]:.0f}, {want[1]:.0f}) placed the magnifier at {got}")
    print(f"{name}: tapped frame ({want[0]:.1f}, {want[1]:.1f}), magnifier {got}")
    inset = wait_until(10, lambda: s.d.execute_script(
        "const i = document.getElementById('inset'), im = document.getElementById('loupe');"
        "return !i.hidden && im.naturalWidth > 0 && i.getBoundingClientRect().width > 20;"))
    check(inset, f"{name}: the magnifier's inset did not appear")
    s.drain_log()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--infocus", required=True, help="path to the infocus binary")
    ap.add_argument("--out", help="directory for the screenshots "
                    "(default $MESON_BUILD_ROOT/web-screens, else ./web-screens)")
    ap.add_argument("--page-dir", help="serve the page files from here, the rest from infocus")
    args = ap.parse_args()

    if not os.path.exists(CHROMIUM):
        skip("chromium is missing")
    if not os.path.exists(CHROMEDRIVER):
        skip("chromedriver (chromium-driver) is missing")
    out = args.out or os.path.join(os.environ.get("MESON_BUILD_ROOT", "."), "web-screens")
    os.makedirs(out, exist_ok=True)

    helped = subprocess.run([args.infocus, "live", "--help"], capture_output=True, text=True)
    if "--listen" not in helped.stdout + helped.stderr:
        skip("this infocus has no web face (`infocus live --help` names no --listen)")

    server = Server(args.infocus)
    sessions = []
    try:
        url = server.wait_url(20)
        if not url:
            err = "".join(server.stderr)
            if server.proc.returncode not in (None, 0) and re.search(
                    r"built without the web|web.*(not built|disabled)|"
                    r"--ui web is not", err):
                skip("this infocus has no web face: " + err.strip().splitlines()[-1])
            print("FAIL: infocus printed no URL within 20 s; its stderr:\n" + err)
            return 1
        api = Api(url)
        first = wait_until(30, api.state)
        if not first:
            print("FAIL: /state gave no state within 30 s")
            return 1
        check(first.get("has_focus_control") is True, "the sim's lens is not motorised "
              "(has_focus_control is not true)")
        check(api.token == TOKEN, f"the printed URL {url} does not carry the token")
        page_url = url
        if args.page_dir:
            page_url = page_proxy(args.page_dir, api.base) + (
                f"?token={api.token}" if api.token else "")
        print(f"server {url}, page {page_url}, lens {first['lens_position']}")

        phone = Session("phone", 360, 640, True, page_url)
        sessions.append(phone)
        check_page(phone, api, "plus1", (0.30, 0.40))
        # The second control takes the magnifier away again.
        phone.d.find_element(By.ID, "loupe-off").click()
        gone = wait_until(10, lambda: (st := api.state()) and st.get("magnifier") is None)
        check(gone, "phone: 'hide loupe' did not clear the magnifier")
        check(wait_until(5, lambda: not phone.d.find_element(By.ID, "inset").is_displayed()),
              "phone: the inset stayed after 'hide loupe'")

        desktop = Session("desktop", 1280, 800, False, page_url)
        sessions.append(desktop)
        check_page(desktop, api, "minus1", (0.62, 0.55))
        shots = [phone.shot(out, "before"), desktop.shot(out, "before")]

        # The sound on through the sweep (muted), so its tone and chime run: an error in them
        # would show in the console's log.
        desktop.d.find_element(By.ID, "audio").click()
        sound = wait_until(5, lambda: desktop.d.execute_script(
            "return typeof audio === 'object' && audio && audio.ctx.state"))
        check(sound == "running", f"the sound toggle did not start the audio ({sound})")
        # Autofocus: the button is disabled while it runs, and the lens ends at the sim's 1 m.
        desktop.d.find_element(By.ID, "af").click()
        t0 = time.monotonic()
        running = wait_until(10, lambda: (st := api.state()) and st["autofocus_running"])
        check(running, "autofocus_running never became true after the Autofocus button")
        if running:
            check(wait_until(5, lambda: not desktop.d.find_element(By.ID, "af").is_enabled()),
                  "the Autofocus button stays enabled while autofocus runs")
        done = wait_until(200, lambda: (st := api.state()) and not st["autofocus_running"]
                          and st, step=0.5)
        # The state that first reads "not running" may come from a frame taken before the lens
        # reached its last position: the lens gets a few more frames to arrive, and must stay.
        def near():
            st = api.state()
            ok = st and abs(st["lens_position"]["dioptres"] - SIM_FOCUS_DPT) <= AF_TOLERANCE_DPT
            return st if ok else None

        if done and not near():
            done = wait_until(15, near) or api.state()
        if done and near():
            time.sleep(1)
            done = api.state()
        lens = done and done["lens_position"]["dioptres"]
        print(f"autofocus: {time.monotonic() - t0:.1f} s, lens {lens} dpt "
              f"(want {SIM_FOCUS_DPT} ± {AF_TOLERANCE_DPT}), status '{done and done['status']}'")
        check(done and abs(lens - SIM_FOCUS_DPT) <= AF_TOLERANCE_DPT,
              f"autofocus left the lens at {lens} dpt, not {SIM_FOCUS_DPT} ± {AF_TOLERANCE_DPT}")
        time.sleep(2)  # a few frames at the new position before the pictures
        shots += [phone.shot(out, "after"), desktop.shot(out, "after")]

        for s in sessions:
            s.drain_log()
            check(not s.severe, f"{s.name}: console errors: {s.severe}")
        print("screenshots in " + os.path.abspath(out) + ": " +
              " ".join(os.path.basename(p) for p in shots))
    except WebDriverException as e:
        print(f"FAIL: the browser: {e.msg if hasattr(e, 'msg') else e}")
        failures.append("browser")
    finally:
        for s in sessions:
            try:
                s.d.quit()
            except WebDriverException:
                pass
        code = server.stop()
    check(code == 0, f"infocus exited {code} on SIGTERM, not 0")
    print(f"{passes} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
