# SPDX-License-Identifier: MIT
"""`infocus-batch export`: the rows `infocus analyze --format csv|jsonl` writes, from the
database. One source gives analyze's own bytes; several get a leading `source` column (CSV) or
key (JSONL) naming each row's source."""
import json
import os
import sys

from .store import REGION_FIELDS

CSV_HEADER = ("frame,timestamp_ns,lens_value,lens_unit,width,height,col,row,x,y,w,h,sharpness,"
              "edge_width_px,blur_sigma_px,blur_width_px,mtf50_cy_px,mtf50p_cy_px,confidence,"
              "status,reason")
FRAME_COLUMNS = ("frame, timestamp_ns, width, height, metric, frame_sharpness, noise_sigma, "
                 "noise_reason, lens_value, lens_unit, lens_dioptres")
REGION_COLUMNS = ("frame, col, row, x, y, w, h, " + ", ".join(REGION_FIELDS) +
                  ", confidence, status, reason")


def _g(v):
    """A number as analyze's CSV writes it (printf %.6g), a missing one as an empty cell."""
    return "" if v is None else "%.6g" % v


def _regions_by_frame(db, sid):
    out = {}
    for r in db.execute(f"SELECT {REGION_COLUMNS} FROM regions WHERE source = ? "
                        "ORDER BY frame, row, col", (sid,)):
        out.setdefault(r[0], []).append(r[1:])
    return out


def _csv(db, sid, path, out, prefix):
    regions = _regions_by_frame(db, sid)
    for f in db.execute(f"SELECT {FRAME_COLUMNS} FROM frames WHERE source = ? ORDER BY frame",
                        (sid,)):
        frame, ts, width, height = f[0], f[1], f[2], f[3]
        lens_value, lens_unit = f[8], f[9]
        head = (f"{prefix}{frame},{ts},{_g(lens_value)},{lens_unit or ''},{width},{height},")
        for col, row, x, y, w, h, *vals, conf, status, reason in regions.get(frame, []):
            ok = status == "ok"
            cells = [_g(v) if ok else "" for v in vals]
            out.write(f"{head}{col},{row},{x},{y},{w},{h},{','.join(cells)},"
                      f"{_g(conf) if ok else ''},{status},{'' if ok else reason or ''}\n")


def _jsonl(db, sid, path, out, with_source):
    regions = _regions_by_frame(db, sid)
    for f in db.execute(f"SELECT {FRAME_COLUMNS} FROM frames WHERE source = ? ORDER BY frame",
                        (sid,)):
        (frame, ts, width, height, metric, sharp, noise, noise_reason, lens_value, lens_unit,
         dioptres) = f
        j = {"source": path} if with_source else {}
        j["frame"] = frame
        j["timestamp_ns"] = ts
        if lens_value is None:
            j["lens_position"] = None
        else:
            j["lens_position"] = {"value": lens_value, "unit": lens_unit}
            if dioptres is not None:
                j["lens_position"]["dioptres"] = dioptres
        j["width"], j["height"] = width, height
        if metric:
            j["metric"] = metric
        if noise is not None:
            j["noise_sigma"] = noise
        elif noise_reason:
            j["noise_sigma"] = None
            j["noise_reason"] = noise_reason
        j["frame_sharpness"] = sharp
        rs = []
        for col, row, x, y, w, h, *vals, conf, status, reason in regions.get(frame, []):
            o = {"col": col, "row": row, "x": x, "y": y, "w": w, "h": h}
            o.update(zip(REGION_FIELDS, vals))
            o["confidence"] = conf
            o["status"] = status
            if status != "ok":
                o["reason"] = reason
            rs.append(o)
        j["regions"] = rs
        out.write(json.dumps(j, separators=(",", ":"), ensure_ascii=False, allow_nan=False))
        out.write("\n")


def export(db, fmt, out, only=None):
    """Writes the complete sources of @p db (all, or the one at path @p only) to @p out in
    @p fmt; returns the number of sources written, or raises LookupError when @p only is not a
    complete source of the database."""
    query = "SELECT id, path FROM sources WHERE status = 'done'"
    args = ()
    if only is not None:
        query += " AND path = ?"
        args = (os.path.abspath(only),)
    sources = db.execute(query + " ORDER BY path", args).fetchall()
    if only is not None and not sources:
        raise LookupError(f"{only} is not a complete source of this database")
    several = len(sources) > 1
    if fmt == "csv" and sources:
        out.write(("source," if several else "") + CSV_HEADER + "\n")
    for sid, path in sources:
        if fmt == "csv":
            # A path holding a comma or quote is quoted as RFC 4180 says.
            cell = '"' + path.replace('"', '""') + '"' if any(c in path for c in ',"\n') else path
            _csv(db, sid, path, out, cell + "," if several else "")
        else:
            _jsonl(db, sid, path, out, several)
    return len(sources)


def write_export(db, fmt, output, only):
    """export() to the file @p output ('-' or None: standard output)."""
    if output in (None, "-"):
        return export(db, fmt, sys.stdout, only)
    with open(output, "w", encoding="utf-8", newline="") as out:
        return export(db, fmt, out, only)
