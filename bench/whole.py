"""Whole-image rate-distortion against JPEG (the paper's Fig. 10 comparison), for bench/run.py.

For each image: `gradmesh convert IMAGE --segment --compact-level 2 --max-error E
[--max-patches P] --report R.json` at several points (E, P) (the whole image, segmented into regions, every pixel
covered), and JPEG's curve on
the same image from `jpeg_match IMAGE --whole --curve` (every quality 1..100, 4:2:0 and 4:4:4,
baseline, progressive and optimised-Huffman, PSNR over all pixels). For each mesh, JPEG's bytes at the mesh's PSNR are interpolated on
JPEG's curve (the smallest-file frontier over every mode, log bytes linear in PSNR), and
the ratio is the zipped compact .gmb over those bytes. E and PSNR are those of the compact file
itself (decoded and re-rendered: the report's "compact" figures), not of the mesh before
quantisation. See bench/README.md.
"""
import io
import json
import math
import os
import struct
import subprocess
import zipfile
import zlib

IMAGES = ["fruits.jpg", "HappyFish.jpg", "astronaut.png"]
# Points "E" (--max-error E, default budget), "E/P" (also --max-patches P, per region) or "E/tN"
# (also --total-patches N: one budget for the whole image, shared out by the regions' measured
# error curves). With the default budget (8000 patches per region, at most one per 8 region
# pixels) --max-error is what stops most regions, so E sets the size; the fixed small budgets
# give the low-rate end of the curve. "3" is convert's default. A trailing "h" adds
# `--colors hermite` (free colour slopes, stored: dearer patches, more PSNR each; the default
# is the bicubic model, whose slopes follow the SVG rule and are not stored).
POINTS = ["2/4", "2/10", "2/t50", "2/t60", "2/t120", "2/t130h", "2/25", "2/t250", "2/50", "2/100",
          "2/400", "8", "5", "4", "3"]  # about rising size

# Compact .gmb levels of the rate-distortion rows (gmb.h, GmbCompactShifts), each point converted
# at each: 2 is ~40 % smaller than level 0 for ~0.2 dB at E 3; 4, 5 and 6 trade more PSNR for
# size, which pays against JPEG at the low-rate end (6, coarser colours, on flat-coloured
# drawings). BENCH_COMPACT_LEVELS=2,4 sets them.
COMPACT_LEVELS = [int(x) for x in os.environ.get("BENCH_COMPACT_LEVELS", "2,4,5,6").split(",")]

# The whole-image mode of convert. The one line to change if --segment's arguments change.
SEGMENT_ARGS = ["--segment"]
# Stand-in while convert has no --segment: the whole image as one rectangular region, through a
# mask that is white everywhere (written here), and this budget where a point gives none. Only a
# development aid; the output says so.
STANDIN_ARGS = ["--max-patches", "1500"]


def has_segment(gm):
    p = subprocess.run([gm, "convert", "--help"], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    return "--segment" in p.stdout


def white_png(path, w, h):
    """An 8-bit grey PNG, white everywhere (no PIL here)."""
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    raw = b"".join(b"\x00" + b"\xff" * w for _ in range(h))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def zipped_size(path, member):
    """Bytes of a .zip archive holding the file as `member`, headers included: deflated (level
    9), or stored when deflate would not make it smaller, as Info-ZIP's zip does (a range-coded
    .gmb does not deflate: deflate's own framing then adds ~3 %). The archive holds the name
    twice (local and central headers): the member is named as a user's file would be
    (IMAGE.gmb), not by this script's long output names."""
    best = None
    for method in (zipfile.ZIP_DEFLATED, zipfile.ZIP_STORED):
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w", method, compresslevel=9 if method else None) as z:
            z.write(path, member)
        if best is None or len(buf.getvalue()) < len(best):
            best = buf.getvalue()
    with open(path + ".zip", "wb") as f:
        f.write(best)
    return len(best)


def jpeg_curve(jm, image):
    p = subprocess.run([jm, image, "--whole", "--curve"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        return {"error": p.stderr.strip() or "exit code %d" % p.returncode}
    return json.loads(p.stdout)


def frontier(curve):
    """JPEG's smallest files: points (bytes, psnr, quality, subsampling) over every mode, kept when
    no smaller file has a PSNR as high; increasing in both bytes and PSNR."""
    pts = sorted((b, ps, q, m["subsampling"]) for m in curve for q, b, ps, _ in m["points"])
    out = []
    for p in pts:
        if not out or p[1] > out[-1][1]:
            if out and p[0] == out[-1][0]:
                out[-1] = p
            else:
                out.append(p)
    return out


def jpeg_at(front, psnr):
    """(interpolated bytes, how) at this PSNR, and the smallest real file reaching it or None.
    Interpolation: log(bytes) linear in PSNR between the two frontier points around it."""
    if not front:
        return None, "no curve", None
    reach = next((p for p in front if p[1] >= psnr), None)
    if psnr < front[0][1]:
        return None, "below q1", reach
    if psnr > front[-1][1]:
        return None, "above q100", None
    for lo, hi in zip(front, front[1:]):
        if lo[1] <= psnr <= hi[1]:
            t = (psnr - lo[1]) / (hi[1] - lo[1])
            b = math.exp(math.log(lo[0]) + t * (math.log(hi[0]) - math.log(lo[0])))
            return b, "q%d %s – q%d %s" % (lo[2], lo[3], hi[2], hi[3]), reach
    return float(front[0][0]), "q%d %s" % (front[0][2], front[0][3]), reach


def jpeg_cells(front, psnr, zipped, fmt):
    """The table's JPEG bytes cell and ratio cell for a mesh of this PSNR and zipped size, and
    the smallest real file reaching the PSNR."""
    jb, how, reach = jpeg_at(front, psnr)
    if jb is not None:
        return "%d (%s)" % (round(jb), how), "%.2f" % (zipped / jb), reach
    if how == "below q1" and reach:
        return ("< %d (q1 %s: %s dB)" % (reach[0], reach[3], fmt(reach[1])),
                "> %.2f" % (zipped / reach[0]), reach)
    if how == "above q100":
        return ("not reached (q100: %d B, %s dB)" % (front[-1][0], fmt(front[-1][1])),
                "< %.2f" % (zipped / front[-1][0]), reach)
    return how, "—", reach


def plot_svg(path, series):
    """A small log-bytes vs PSNR chart: per image, JPEG's frontier (line) and the meshes (dots)."""
    mesh = [p for s in series for p in s["mesh"]]
    top = max(p[1] for p in mesh) + 6 if mesh else 1e9  # JPEG's curve up to 6 dB above the meshes
    series = [dict(s, jpeg=[p for p in s["jpeg"] if p[1] <= top]) for s in series]
    pts = [(p[0], p[1]) for s in series for p in s["jpeg"] + s["mesh"]]
    if not pts:
        return
    W, H, L, B, R, T = 640, 420, 60, 40, 150, 20
    x0, x1 = math.floor(min(p[1] for p in pts)), math.ceil(max(p[1] for p in pts))
    step = 1 if x1 - x0 <= 12 else 2 if x1 - x0 <= 24 else 5
    y0 = math.floor(math.log10(min(p[0] for p in pts)) * 4) / 4
    y1 = math.ceil(math.log10(max(p[0] for p in pts)) * 4) / 4
    X = lambda v: L + (v - x0) / max(x1 - x0, 1e-9) * (W - L - R)
    Y = lambda b: H - B - (math.log10(b) - y0) / max(y1 - y0, 1e-9) * (H - B - T)
    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif"'
         ' font-size="11"><rect width="100%%" height="100%%" fill="white"/>' % (W, H)]
    for d in range(int(x0), int(x1) + 1, step):
        o.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/><text x="%.1f" y="%d" '
                 'text-anchor="middle">%d</text>' % (X(d), T, X(d), H - B, X(d), H - B + 14, d))
    for e in range(int(math.floor(y0)), int(math.ceil(y1)) + 1):
        for m in (1, 2, 5):
            b = m * 10 ** e
            if y0 <= math.log10(b) <= y1:
                o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/><text x="%d" '
                         'y="%.1f" text-anchor="end">%s</text>' % (
                             L, Y(b), W - R, Y(b), L - 4, Y(b) + 4,
                             "%g KB" % (b / 1000) if b >= 1000 else "%d B" % b))
    o.append('<text x="%d" y="%d" text-anchor="middle">PSNR (dB), all pixels</text>' % (
        (L + W - R) / 2, H - 6))
    colours = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"]
    for k, s in enumerate(series):
        c = colours[k % len(colours)]
        line = " ".join("%.1f,%.1f" % (X(p[1]), Y(p[0])) for p in s["jpeg"])
        if line:
            o.append('<polyline points="%s" fill="none" stroke="%s"/>' % (line, c))
        for p in s["mesh"]:
            o.append('<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s"/>' % (X(p[1]), Y(p[0]), c))
        o.append('<text x="%d" y="%d" fill="%s">%s</text>' % (W - R + 10, T + 12 + 30 * k, c,
                                                              s["name"]))
        o.append('<text x="%d" y="%d" fill="%s" font-size="9">line JPEG, dots .gmb.zip</text>' % (
            W - R + 10, T + 24 + 30 * k, c))
    o.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(o) + "\n")


def parse_point(text):
    """"E", "E/P" or "E/tN", each with an optional trailing "h" (hermite colours) ->
    (E, P or None, N or None, hermite)."""
    text = text.strip()
    hermite = text.endswith("h")
    e, _, p = text.rstrip("h").partition("/")
    if p.startswith("t"):
        return float(e), None, int(p[1:]), hermite
    return float(e), (int(p) if p else None), None, hermite


def section(run_convert, fmt, table, log, gm, jm, samples, out, only, timeout, points=None):
    """Prints the whole-image section (Markdown) on stdout. points: strings "E" or "E/P"."""
    points = [parse_point(t) for t in (points or POINTS)]
    segment = has_segment(gm)
    body, series, curves = [], [], []
    for name in IMAGES:
        label = name + " (whole)"
        if only not in label:
            continue
        image = os.path.join(samples, name)
        stem = "whole_" + os.path.splitext(name)[0]
        log("== %s: JPEG curve" % label)
        jc = jpeg_curve(jm, image)
        front = [] if "error" in jc else frontier(jc["curve"])
        # The issue's own baseline: OpenImageIO's JPEG writer (standard Huffman tables) alone.
        front_base = [] if "error" in jc else frontier(
            [m for m in jc["curve"] if "/" not in m["subsampling"]])
        if "error" in jc:
            curves.append("- %s: JPEG curve FAILED: %s" % (name, jc["error"]))
        else:
            curves.append("- %s (%d×%d): JPEG from %s B (q1, %s dB) to %s B (q100, %s dB); "
                          "the frontier has %d of %d encodes; OpenImageIO's baseline writer "
                          "alone from %s B (q1) to %s B (q100)" % (
                              name, jc["width"], jc["height"], front[0][0], fmt(front[0][1]),
                              front[-1][0], fmt(front[-1][1]), len(front),
                              sum(len(m["points"]) for m in jc["curve"]), front_base[0][0],
                              front_base[-1][0]))
        extra = SEGMENT_ARGS
        if not segment:
            if "error" in jc:
                body.append([name] + ["—"] * 15 + ["FAILED: no size for the stand-in mask"])
                continue
            mask = os.path.join(out, stem + "_white.png")
            white_png(mask, jc["width"], jc["height"])
            extra = ["--mask", mask]
        mesh_pts = []
        for (e, budget, total, hermite), level in [(p, lv) for p in points for lv in COMPACT_LEVELS]:
            base = os.path.join(out, "%s_E%g%s%s%s_L%d" % (stem, e, "_P%d" % budget if budget else "",
                                                           "_T%d" % total if total else "",
                                                           "_hermite" if hermite else "", level))
            gmb, rep = base + ".gmb", base + ".json"
            args = ["--compact-level", str(level), "--max-error", "%g" % e]
            if hermite:
                args += ["--colors", "hermite"]
            if budget:
                args += ["--max-patches", str(budget)]
            elif total and segment:
                args += ["--total-patches", str(total)]
            elif not segment:
                args += STANDIN_ARGS
            ok, r, wall, _ = run_convert(gm, image, None, gmb, rep, extra + args, timeout)
            bcell = str(budget) if budget else "%d in all" % total if total else "default"
            if not ok:
                log("   E %g, budget %s, level %d failed: %s" % (e, bcell, level, r))
                body.append([name, "%g" % e, bcell, str(level)] + ["—"] * 10 +
                            ["%s (wall, failed)" % fmt(wall), "—", "FAILED: %s" % r])
                continue
            # The compact file's own figures (older gradmesh: the mesh's).
            err = r.get("compact", {}).get("error", r["error"])
            psnr = err["psnr"]
            compact = os.path.getsize(gmb)
            zipped = zipped_size(gmb, os.path.splitext(name)[0] + ".gmb")
            regions = r.get("segments", {}).get("count", len(r["regions"]))
            jcell, ratio, reach = jpeg_cells(front, psnr, zipped, fmt)
            _, ratio_base, _ = jpeg_cells(front_base, psnr, zipped, fmt)
            rcell = "%d (q%d %s)" % (reach[0], reach[2], reach[3]) if reach else "—"
            notes = []
            if "compact" in r:
                notes.append("mesh before quantisation %s dB" % fmt(r["error"]["psnr"]))
            if compact != r["bytes"]["gmb_compact"]:
                notes.append("report's gmb_compact %d B" % r["bytes"]["gmb_compact"])
            seg = r.get("segments", {})
            if seg.get("failed"):
                notes.append("%d region(s) failed (left to the base mesh)" % seg["failed"])
            if seg.get("holes_filled"):
                notes.append("%d converted with holes filled" % seg["holes_filled"])
            if seg.get("thin_parts_apart"):
                notes.append("%d converted as a core plus its thin parts apart" %
                             seg["thin_parts_apart"])
            if seg.get("base_patches"):
                notes.append("base mesh %d patches" % seg["base_patches"])
            if seg.get("region_uncovered"):
                notes.append("%.2f %% of pixels only under the base mesh" %
                             (100 * seg["region_uncovered"]))
            notes.append("wall with --report %s s" % fmt(wall))
            log("   E %g, budget %s, level %d: %d regions, %d patches, PSNR %.2f, %d B zipped, "
                "JPEG %s, %.1f s" % (e, bcell, level, regions, r["patches"], psnr, zipped, jcell,
                                     r["io_seconds"]["end_to_end"]))
            mesh_pts.append((zipped, psnr))
            if total and segment:
                bcell = "%d in all (%d conversions)" % (total, seg.get("conversions", 0))
            else:
                bcell = str(r.get("max_patches", budget)) + (
                    "" if budget else " (default)" if segment else " (stand-in)")
            if hermite:
                bcell += ", `--colors hermite`"
            body.append([name, "%g" % e, bcell, str(level), str(regions), str(r["patches"]),
                         fmt(err["E"]),
                         fmt(psnr), str(compact), str(zipped), jcell, ratio, ratio_base, rcell,
                         fmt(r["io_seconds"]["end_to_end"]),
                         "%.3f %%" % (100 * err["uncovered"]), "; ".join(notes)])
        series.append({"name": name, "jpeg": [(p[0], p[1]) for p in front], "mesh": mesh_pts})

    chart = os.path.join(out, "whole_rd.svg")
    plot_svg(chart, series)
    print()
    print("### Whole image against JPEG (Fig. 10)")
    print()
    if segment:
        print("Each row: `gradmesh convert IMAGE %s --compact-level L --max-error E "
              "[--max-patches P | --total-patches N] [--colors hermite] --report R.json` (E target, "
              "patch budget P per region or N for the whole image, compact level L); E and PSNR "
              "are the compact file's own (decoded and re-rendered)." %
              " ".join(SEGMENT_ARGS))
    else:
        print("**STAND-IN, not `--segment`** (this gradmesh has no `--segment`): each row is "
              "`gradmesh convert IMAGE --mask WHITE.png --compact-level L --max-error E "
              "--max-patches P` "
              "with a mask that is white everywhere, so the whole image is one rectangular "
              "region; where the point gives no P: `%s`." % " ".join(STANDIN_ARGS))
    print("PSNR, E and uncovered are over all pixels of the image. JPEG: `jpeg_match IMAGE "
          "--whole --curve` (qualities 1–100; 4:2:0 and 4:4:4; OpenImageIO's baseline and "
          "progressive writers and libjpeg-turbo with optimised Huffman tables); its bytes "
          "at the mesh's PSNR are interpolated (log bytes linear in PSNR) on the smallest-file "
          "frontier; ratio = zipped `.gmb` / those bytes (< 1: the mesh is smaller). The "
          "baseline ratio is against OpenImageIO's baseline writer alone (standard Huffman "
          "tables), the bench's JPEG before 2026-11-25 afternoon. Chart: `%s`." % chart)
    print()
    print("\n".join(curves))
    print()
    print(table(["image", "E target", "patch budget", "level", "regions", "patches", "E", "PSNR",
                 "compact .gmb (B)", ".gmb zipped (B)", "JPEG at same PSNR (B, interpolated)",
                 "zipped / JPEG", "zipped / baseline JPEG", "smallest JPEG ≥ PSNR (B)",
                 "end-to-end (s)", "uncovered",
                 "notes"], body))
