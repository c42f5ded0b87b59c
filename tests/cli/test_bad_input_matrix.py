#!/usr/bin/env python3
# The bad-input matrix: every row of bad_input_matrix.txt is a command line, the input it is
# given (made here, before the row runs), the exit status it must end with (2 usage, 1 runtime)
# and a regular expression its message must match, naming the file, field or option at fault.
# A row also fails when the command dies by a signal, runs past its time-out (60 s) or prints a
# sanitizer report. Ends with the whole table (inputs, expected, got, pass) and a count line.
# Usage: test_bad_input_matrix.py PATH_TO_INFOCUS [TABLE]
import json
import os
import re
import shlex
import signal
import struct
import subprocess
import sys
import tempfile
import time
import zlib

TIMEOUT_S = 60
SANITIZER = re.compile(r"runtime error:|AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer")


def y4m(path, header, frames):
    with open(path, "wb") as f:
        f.write(header.encode() + b"\n")
        for frame in frames:
            f.write(b"FRAME\n" + frame)


def recording(infocus, path, frames=3):
    subprocess.run([infocus, "record", "sim:size=32x24,pace=fast", "-o", path, "--frames",
                    str(frames)], check=True, capture_output=True)


def craft_record_length(path, length):
    """Gives the second record of the recording at @p path a payload length of @p length, with
    both CRCs recomputed, as a crafted file would have them."""
    frames = os.path.join(path, "frames.bin")
    data = bytearray(open(frames, "rb").read())
    first = struct.unpack_from("<Q", data, 8)[0]
    at = 128 + first
    struct.pack_into("<Q", data, at + 8, length)
    struct.pack_into("<I", data, at + 124, zlib.crc32(bytes(data[at:at + 124])))
    open(frames, "wb").write(data)


def png(path, width, height, depth=8):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    rows = zlib.compress(b"\0" * ((width + 1) * height))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", rows) + chunk(b"IEND", b""))


def jpeg(path, size="64x48"):
    subprocess.run(["convert", "-size", size, "gradient:", path], check=True, capture_output=True)
    return open(path, "rb").read()


def avi(path, jpeg_frame, count, width=64, height=48, keep=None):
    """An MJPEG AVI of @p count copies of @p jpeg_frame whose headers list @p count frames; only
    the first @p keep frame chunks are written when given (a truncated file)."""
    def chunk(fourcc, body):
        return fourcc + struct.pack("<I", len(body)) + body + (b"\0" if len(body) % 2 else b"")

    def lst(kind, body):
        return b"LIST" + struct.pack("<I", len(body) + 4) + kind + body
    avih = struct.pack("<10I4I", 100000, 0, 0, 0x10, count, 0, 1, len(jpeg_frame), width, height, 0, 0, 0, 0)
    strh = b"vidsMJPG" + struct.pack("<IHHIIIIIIIIhhhh", 0, 0, 0, 0, 1, 10, 0, count, len(jpeg_frame), 0xFFFFFFFF, 0, 0, 0, width, height)
    strf = struct.pack("<IiiHH4sIiiII", 40, width, height, 1, 24, b"MJPG", width * height * 3, 0, 0, 0, 0)
    hdrl = lst(b"hdrl", chunk(b"avih", avih) + lst(b"strl", chunk(b"strh", strh) + chunk(b"strf", strf)))
    frames = [chunk(b"00dc", jpeg_frame) for _ in range(count)]
    index = b""
    offset = 4
    for fr in frames:
        index += b"00dc" + struct.pack("<III", 0x10, offset, len(jpeg_frame))
        offset += len(fr)
    body = b"AVI " + hdrl + lst(b"movi", b"".join(frames)) + chunk(b"idx1", index)
    data = b"RIFF" + struct.pack("<I", len(body)) + body
    if keep is not None:
        data = data[:data.index(b"00dc") + len(frames[0]) * keep]
    open(path, "wb").write(data)


def jsonl(infocus, path, change=None):
    out = subprocess.run([infocus, "analyze", "sim:size=64x48,pace=fast", "--frames", "2", "--grid",
                          "2x2"], check=True, capture_output=True, text=True).stdout
    if change:  # the second record, changed as a dict
        lines = out.splitlines(keepends=True)
        record = json.loads(lines[1])
        change(record)
        lines[1] = json.dumps(record) + "\n"
        out = "".join(lines)
    open(path, "w").write(out)


# Inputs a row names (column 3): each makes the file or directory {in}.
def make_input(name, path, infocus):
    frame = bytes(range(256)) * 2
    if name == "-":
        return
    makers = {
        "y4m-cut-frame": lambda: y4m(path, "YUV4MPEG2 W16 H16 F30:1 C420jpeg", [frame[:384], frame[:100]]),
        "y4m-zero-width": lambda: y4m(path, "YUV4MPEG2 W0 H16 F30:1 Cmono", []),
        "y4m-huge-size": lambda: y4m(path, "YUV4MPEG2 W100000 H100000 F30:1 Cmono", [frame]),
        "y4m-colour-space": lambda: y4m(path, "YUV4MPEG2 W16 H16 F30:1 C411", [frame]),
        "y4m-no-marker": lambda: open(path, "wb").write(b"YUV4MPEG2 W16 H16 F30:1 Cmono\nFRAMX\n" + frame[:256]),
        "y4m-not-y4m": lambda: open(path, "wb").write(b"RIFF....AVI LIST" + frame),
        "rec": lambda: recording(infocus, path),
        "rec-length-2^64": lambda: (recording(infocus, path), craft_record_length(path, 2**64 - 1)),
        "rec-length-2^63": lambda: (recording(infocus, path), craft_record_length(path, 2**63)),
        "rec-length-file": lambda: (recording(infocus, path), craft_record_length(path, 10**6)),
        "rec-torn-tail": lambda: (recording(infocus, path), os.truncate(os.path.join(path, "frames.bin"), 128 * 3 + 768 * 2 + 50)),
        "rec-no-frames": lambda: (recording(infocus, path), os.remove(os.path.join(path, "frames.bin"))),
        "rec-header-garbage": lambda: (recording(infocus, path), open(os.path.join(path, "header.json"), "w").write("{\"format\": ")),
        "rec-header-version": lambda: (recording(infocus, path), rewrite_header(path, "format_version", 99)),
        "rec-header-width": lambda: (recording(infocus, path), rewrite_header(path, "width_px", "wide")),
        "rec-header-format": lambda: (recording(infocus, path), rewrite_header(path, "pixel_format", "XXXX")),
        "png-huge": lambda: png(path, 17000, 17000),
        "png-zero": lambda: open(path, "wb").write(b""),
        "png-garbage": lambda: open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + frame),
        "png-16bit": lambda: png(path, 16, 16, 16),
        "jpeg-cut": lambda: open(path, "wb").write(jpeg(path + ".src.jpg")[:200]),
        "jpeg-huge-header": lambda: open(path, "wb").write(huge_jpeg(jpeg(path + ".src.jpg"))),
        "avi-cut": lambda: avi(path, jpeg(path + ".jpg"), 10, keep=1),
        "avi-garbage": lambda: open(path, "wb").write(b"RIFF\x10\x00\x00\x00AVI LIST" + frame),
        "jsonl-garbage": lambda: open(path, "w").write("{\"frame\": 0, \"width\n"),
        "jsonl-ok": lambda: jsonl(infocus, path),
        "jsonl-empty": lambda: open(path, "w").write(""),
        "jsonl-regions-string": lambda: jsonl(infocus, path, lambda r: r.update(regions="x")),
        "jsonl-width-negative": lambda: jsonl(infocus, path, lambda r: r.update(width=-5)),
        "jsonl-not-json": lambda: open(path, "w").write("not json at all\n"),
        "dir-empty": lambda: os.mkdir(path),
        "dir-text-files": lambda: (os.mkdir(path), open(os.path.join(path, "a.txt"), "w").write("x")),
        "fifo": lambda: os.mkfifo(path),
        "text-file": lambda: open(path, "w").write("x\n"),
    }
    makers[name]()


def rewrite_header(path, field, value):
    header = os.path.join(path, "header.json")
    h = json.load(open(header))
    h[field] = value
    json.dump(h, open(header, "w"))


def huge_jpeg(data):
    """@p data with its frame header claiming 60000 x 60000 pixels."""
    data = bytearray(data)
    for marker in (b"\xff\xc0", b"\xff\xc2"):
        at = data.find(marker)
        if at >= 0:
            struct.pack_into(">HH", data, at + 5, 60000, 60000)
            break
    return bytes(data)


def run_row(infocus, tmp, row):
    want, pattern, input_name, command = row
    case = tempfile.mkdtemp(dir=tmp)
    ext = {"y4m": ".y4m", "rec": "", "png": ".png", "jpe": ".jpg", "avi": ".avi", "jso": ".jsonl"}
    path = os.path.join(case, "in" + ext.get(input_name[:3], ""))
    make_input(input_name, path, infocus)
    args = [a.replace("{in}", path).replace("{tmp}", case) for a in shlex.split(command)]
    pattern = pattern.replace("{in}", re.escape(path)).replace("{tmp}", re.escape(case))
    sig = None
    if args[0].startswith("@SIG"):  # @SIGINT@0.3 record ...: the signal, that many seconds in
        sig, after = args[0][1:].split("@")
        args = args[1:]
    start = time.monotonic()
    proc = subprocess.Popen([infocus] + args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, errors="replace")
    if sig:
        # Seconds into the command's own run: a sanitizer build takes about a second to reach
        # main(), and before main() no program can catch a signal.
        time.sleep(float(after) + STARTUP_S)
        proc.send_signal(getattr(signal, sig))
    try:
        _, err = proc.communicate(timeout=TIMEOUT_S)
        got = str(proc.returncode) if proc.returncode >= 0 else "signal " + signal.Signals(-proc.returncode).name
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
        got = "hang"
    seconds = time.monotonic() - start
    ok = got == want and re.search(pattern, err) is not None and not SANITIZER.search(err)
    return got, ok, err, seconds


STARTUP_S = 0.0


def startup_seconds(infocus):
    """The slowest of three `infocus --version` runs: how long the binary takes to start."""
    worst = 0.0
    for _ in range(3):
        t0 = time.monotonic()
        subprocess.run([infocus, "--version"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        worst = max(worst, time.monotonic() - t0)
    return worst


def main():
    global STARTUP_S
    infocus = os.path.abspath(sys.argv[1])
    STARTUP_S = startup_seconds(infocus)
    print("start-up of %s: %.3f s (added to the signal rows' delays)" % (infocus, STARTUP_S))
    table = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "bad_input_matrix.txt")
    rows = []
    for line in open(table):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f.strip() for f in line.split(" | ", 3)]
        if len(fields) != 4:
            sys.exit(f"{table}: malformed row: {line}")
        rows.append(fields)
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for row in rows:
            got, ok, err, seconds = run_row(infocus, tmp, row)
            results.append((row, got, ok))
            if not ok:
                print(f"FAIL: infocus {row[3]} (input {row[2]}): got {got}, want {row[0]} "
                      f"matching /{row[1]}/ after {seconds:.1f} s; stderr:\n  " +
                      "\n  ".join(err.strip().splitlines()[-6:]))
    print(f"\n{'command line':<58} {'input':<20} {'want':>4} {'got':>6}  pass")
    for (want, _, input_name, command), got, ok in results:
        print(f"{command[:58]:<58} {input_name:<20} {want:>4} {got:>6}  {'yes' if ok else 'NO'}")
    failed = sum(1 for r in results if not r[2])
    print(f"bad-input matrix: {len(results) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
