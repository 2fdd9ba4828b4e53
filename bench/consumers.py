#!/usr/bin/env python3
"""What users open: each sample at the defaults in both colour models, and the default files
as their consumers render them (Inkscape for the SVG, Ghostscript and pdftocairo for the PDF).

    python3 bench/consumers.py [--build build] [--out bench-out/consumers] [--only TEXT]

Prints one Markdown table (stdout; progress on stderr):
  - patches, E and PSNR against the image, compact .gmb bytes: bicubic (the default) and hermite;
  - bicubic at equal compact bytes: the bicubic PSNR interpolated at hermite's compact bytes
    (bicubic runs at 1x, 1.5x, 2x, 3x and 4x the default patch budget, or lower error targets
    for whole images), against hermite's PSNR;
  - the default SVG: bytes, bytes per patch, gzipped bytes;
  - Inkscape: E (and 99th percentile) from our render, composited over white and eroded 1 px;
    E from the image; seconds and peak MB;
  - the default PDF: bytes per patch; Ghostscript's and pdftocairo's E from our render.
"""
import argparse
import gzip
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run(cmd, **kw):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    if r.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), r.returncode, r.stderr[-400:]))
    return r


def figures(text):
    out = {}
    for line in text.splitlines():
        if ": " in line:
            k, v = line.split(": ", 1)
            try:
                out[k] = float(v)
            except ValueError:
                pass
    return out


class Bench:
    def __init__(self, gm, out):
        self.gm, self.out = gm, out
        self.home = os.path.join(out, "inkscape-home")
        os.makedirs(self.home, exist_ok=True)

    def path(self, name):
        return os.path.join(self.out, name)

    def convert(self, args, name, colors, extra=()):
        gmb, rep = self.path(name + ".gmb"), self.path(name + ".json")
        run([self.gm, "convert"] + args + ["--colors", colors, "-o", gmb, "--report", rep]
            + list(extra))
        r = json.load(open(rep))
        return {"patches": r["patches"], "E": r["error"]["E"], "psnr": r["error"]["psnr"],
                "compact": r["compact"]["bytes"], "gmb": gmb}

    def compare(self, a, b, extra=()):
        return figures(run([self.gm, "compare", a, b] + list(extra)).stdout)

    def timed(self, cmd, env=None):
        r = run(["/usr/bin/time", "-f", "TIME %e %M"] + cmd, env=env)
        m = re.search(r"TIME ([0-9.]+) ([0-9]+)", r.stderr)
        return float(m.group(1)), int(m.group(2)) / 1024.0

    def inkscape(self, svg, png):
        env = dict(os.environ, HOME=self.home, XDG_CONFIG_HOME=self.home)
        return self.timed(["inkscape", "--export-type=png", "--export-filename=" + png, svg], env)

    def consumers(self, name, gmb, image, mask, patches):
        row = {}
        svg, ours = self.path(name + ".svg"), self.path(name + "_ours.png")
        run([self.gm, "convert", gmb, "-o", svg])
        data = open(svg, "rb").read()
        row["svg"], row["svg_gz"] = len(data), len(gzip.compress(data, 9))
        row["svg_per_patch"] = len(data) / patches
        run([self.gm, "render", gmb, "-o", ours])
        ink = self.path(name + "_ink.png")
        row["ink_s"], row["ink_mb"] = self.inkscape(svg, ink)
        f = self.compare(ours, ink, ["--background", "white", "--erode", "1"])
        row["ink_E"], row["ink_p99"] = f["E"], f["p99"]
        # Against the image over the object's pixels (the mask, else our render's coverage).
        sel = ["--mask", mask] if mask else []
        row["ink_img_E"] = self.compare(image, ink, sel)["E"] if mask else self.compare(ink, image)["E"]
        row["ours_img_E"] = self.compare(image, ours, sel)["E"] if mask else self.compare(ours, image)["E"]
        pdf = self.path(name + ".pdf")
        run([self.gm, "convert", gmb, "-o", pdf])
        row["pdf_per_patch"] = os.path.getsize(pdf) / patches
        gs, pc = self.path(name + "_gs.png"), self.path(name + "_pc")
        run(["gs", "-q", "-dNOPAUSE", "-dBATCH", "-sDEVICE=pngalpha", "-r72",
             "-sOutputFile=" + gs, pdf])
        run(["pdftocairo", "-png", "-r", "72", "-singlefile", pdf, pc])
        for key, png in (("gs_E", gs), ("pc_E", pc + ".png")):
            row[key] = self.compare(ours, png, ["--background", "white", "--erode", "1"])["E"]
        return row


def at_bytes(points, target):
    """PSNR interpolated (linearly in log bytes) at `target` bytes; None when out of range."""
    import math
    pts = sorted((p["compact"], p["psnr"]) for p in points)
    for (b0, p0), (b1, p1) in zip(pts, pts[1:]):
        if b0 <= target <= b1 and b1 > b0:
            w = (math.log(target) - math.log(b0)) / (math.log(b1) - math.log(b0))
            return p0 + w * (p1 - p0)
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench-out", "consumers"))
    ap.add_argument("--only", default="")
    a = ap.parse_args()
    gm = os.path.join(a.build, "app", "gradmesh")
    os.makedirs(a.out, exist_ok=True)
    b = Bench(gm, a.out)
    S = lambda f: os.path.join(ROOT, "samples", f)
    rows = [
        ("apple + mask", "apple", [S("apple.jpg"), "--mask", S("apple_mask.png")], S("apple_mask.png"), False),
        ("horse (GrabCut)", "horse", [S("horse.png")], None, False),
        ("plant + matte", "plant", [S("plant.jpg"), "--mask", S("plant_matte.png")], S("plant_matte.png"), False),
        ("pic1 (7 holes)", "pic1", [S("pic1.png")], None, False),
        ("fruits, whole", "fruits", [S("fruits.jpg"), "--segment"], None, True),
        ("HappyFish, whole", "fish", [S("HappyFish.jpg"), "--segment"], None, True),
        ("astronaut, whole", "astronaut", [S("astronaut.png"), "--segment"], None, True),
    ]
    header = ["sample", "patches B / H", "E B / H", "PSNR B / H", "compact B / H (B)",
              "B's PSNR at H's bytes", ".svg (B)", "B/patch", ".svgz (B)",
              "Inkscape E / p99 from ours", "Inkscape E from image (ours)", "Inkscape s / MB",
              "PDF B/patch", "gs / pdftocairo E"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for label, name, args, mask, whole in rows:
        if a.only not in label:
            continue
        log("== " + label)
        t0 = time.time()
        bic = b.convert(args, name, "bicubic")
        her = b.convert(args, name + "_hermite", "hermite")
        sweep = [bic]
        if whole:
            for e in ("2.5", "2"):
                sweep.append(b.convert(args, "%s_e%s" % (name, e), "bicubic", ["--max-error", e]))
        else:
            for p in ("600", "800", "1200", "1600"):
                sweep.append(b.convert(args, "%s_p%s" % (name, p), "bicubic", ["--max-patches", p]))
        eq = at_bytes(sweep, her["compact"])
        c = b.consumers(name, bic["gmb"], args[0], mask, bic["patches"])
        cells = [
            label,
            "%d / %d" % (bic["patches"], her["patches"]),
            "%.2f / %.2f" % (bic["E"], her["E"]),
            "%.2f / %.2f" % (bic["psnr"], her["psnr"]),
            "%s / %s" % (format(bic["compact"], ","), format(her["compact"], ",")),
            ("%.2f (H %.2f)" % (eq, her["psnr"])) if eq is not None
            else "> %s B (H %.2f)" % (format(max(p["compact"] for p in sweep), ","), her["psnr"]),
            format(c["svg"], ","), "%.0f" % c["svg_per_patch"], format(c["svg_gz"], ","),
            "%.2f / %.0f" % (c["ink_E"], c["ink_p99"]),
            "%.2f (%.2f)" % (c["ink_img_E"], c["ours_img_E"]),
            "%.1f / %.0f" % (c["ink_s"], c["ink_mb"]),
            "%.0f" % c["pdf_per_patch"],
            "%.2f / %.2f" % (c["gs_E"], c["pc_E"]),
        ]
        print("| " + " | ".join(cells) + " |", flush=True)
        log("   %.0f s" % (time.time() - t0))


if __name__ == "__main__":
    main()
