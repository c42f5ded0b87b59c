# SPDX-License-Identifier: MIT
"""Finding the sources under the paths of a batch, and what identifies their content: the files
that make each source up, their total size, newest mtime and a hash of names and bytes."""
import glob
import hashlib
import os
from dataclasses import dataclass, field

# The image extensions `analyze` reads from a directory (replay/image_reader.cpp).
IMAGE_EXTENSIONS = {"jpg", "jpeg", "png", "tif", "tiff", "bmp", "pgm", "ppm", "pnm", "pbm", "webp"}
# Files a folder walk takes as videos; a file named on the command line is taken whatever its
# name, as `analyze` takes it.
VIDEO_EXTENSIONS = {"y4m", "mp4", "m4v", "mkv", "webm", "avi", "mov", "mpg", "mpeg", "ts", "ogv",
                    "wmv", "flv", "mjpeg", "mjpg", "h264", "h265", "hevc"}
RECORDING_HEADER = "header.json"
RECORDING_FRAMES = "frames.bin"
HASH_CHUNK = 1 << 20


def _extension(name):
    dot = name.rfind(".")
    return name[dot + 1:].lower() if dot > 0 else ""


@dataclass
class Source:
    """One source as `analyze` opens it: its path (the key of the results), kind and files."""
    path: str
    kind: str  # recording, video, image, images (a directory), glob
    files: list = field(default_factory=list)
    error: str = ""  # why it cannot be read, found while searching

    @property
    def root(self):
        """The folder the files' names are hashed relative to."""
        return self.path if self.kind in ("recording", "images") else os.path.dirname(self.path)

    def identity(self):
        """(size, mtime_ns) of the files now; raises OSError when one cannot be read."""
        size, mtime = 0, 0
        for f in self.files:
            st = os.stat(f)
            size += st.st_size
            mtime = max(mtime, st.st_mtime_ns)
        return size, mtime


class DiscoveryError(Exception):
    """A path of the command line that names no source."""


def _images_in(directory, names):
    return [os.path.join(directory, n) for n in sorted(names)
            if not n.startswith(".") and _extension(n) in IMAGE_EXTENSIONS
            and os.path.isfile(os.path.join(directory, n))]


def _recording(directory):
    files = [os.path.join(directory, n) for n in sorted(os.listdir(directory))
             if os.path.isfile(os.path.join(directory, n))]
    return Source(directory, "recording", files)


def _walk(directory, out, seen):
    real = os.path.realpath(directory)
    if real in seen:  # a link back up the tree
        return
    seen.add(real)
    try:
        names = sorted(os.listdir(directory))
    except OSError as e:
        why = f"cannot read directory {directory}: {e.strerror}; check its permissions"
        out.append(Source(directory, "unreadable", [], why))
        return
    # A recording is a directory with its header (or its frames without one: damaged, and
    # reported so when it is opened); nothing under it is another source.
    if RECORDING_HEADER in names or RECORDING_FRAMES in names:
        out.append(_recording(directory))
        return
    images = _images_in(directory, names)
    if images:
        out.append(Source(directory, "images", images))
    for n in names:
        p = os.path.join(directory, n)
        if n.startswith("."):
            continue
        if os.path.isdir(p):
            _walk(p, out, seen)
        elif os.path.isfile(p) and _extension(n) in VIDEO_EXTENSIONS:
            out.append(Source(p, "video", [p]))


def discover(paths):
    """The sources under @p paths, in order, each once: a recording, a video or image file, a
    directory of images or a glob of them as one source each, and a folder of these searched
    through. Raises DiscoveryError for a path that does not exist or matches nothing."""
    out, seen = [], set()
    for given in paths:
        p = os.path.abspath(given)
        if os.path.isdir(p):
            _walk(p.rstrip("/") or "/", out, seen)
        elif os.path.exists(p):
            ext = _extension(os.path.basename(p))
            out.append(Source(p, "image" if ext in IMAGE_EXTENSIONS else "video", [p]))
        elif any(c in given for c in "*?["):
            files = sorted(f for f in glob.glob(p) if not os.path.isdir(f))
            if not files:
                raise DiscoveryError(f"no file matches the pattern '{given}'; check the path")
            out.append(Source(p, "glob", files))
        else:
            raise DiscoveryError(f"{given} does not exist; give a recording, video, image, "
                                 "directory of images, glob, or a folder holding them")
    unique, keys = [], set()
    for s in out:
        if s.path not in keys:
            keys.add(s.path)
            unique.append(s)
    return unique


def content_hash(files, root):
    """BLAKE2b-128 of the files' names (relative to @p root) and bytes, in order, as hex."""
    h = hashlib.blake2b(digest_size=16)
    buf = bytearray(HASH_CHUNK)  # one buffer for every read: no allocation a chunk
    view = memoryview(buf)
    for f in files:
        name = os.path.relpath(f, root).encode()
        h.update(len(name).to_bytes(8, "little") + name)
        with open(f, "rb", buffering=0) as fp:
            h.update(os.fstat(fp.fileno()).st_size.to_bytes(8, "little"))
            while n := fp.readinto(buf):
                h.update(view[:n])
    return h.hexdigest()
