"""Whole images against the flat-colour tracers, measured on what the user opens.

    python3 bench/tracers.py [IMAGE ...]        (outputs under bench-out/tracers/)
    python3 bench/tracers.py --from bench-out/tracers/results.json   (the tables again)

For each image (flattened over white first, so that every tool sees the same pixels):
- gradmesh: `convert --segment --max-error E [--total-patches N]` at several points (E 3 alone is
  the default), written as the default SVG (with the mesh script) and as `--svg-script none`;
- vtracer (npm @neplex/vectorizer) and imagetracerjs (npm imagetracerjs) at several presets
  (bench/tracers.mjs), installed here from npm into bench-out/tracers/npm (never committed).
Every SVG is rendered by Inkscape at the image's size and scored against the image by
stray_pixels (both over white): E, PSNR, and the stray pixels (error > 48 more than 2 px from a
strong edge). Bytes are the SVG file, raw and gzipped (-9).

Then, for each tracer point: our SVG's bytes at the tracer's PSNR (interpolated on our curve:
the front of our points, those no other point beats in both bytes and PSNR; log bytes linear
in PSNR) over the tracer's bytes, raw and gzipped ("≤ x" where the tracer's
PSNR lies below our whole curve: our smallest file that reaches it); and our PSNR at the
tracer's bytes. Prints markdown tables; writes bench-out/tracers/results.json. GRADMESH and STRAY_PIXELS
name other builds of the two programs.
"""
import gzip
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench-out", "tracers")
GM = os.environ.get("GRADMESH", os.path.join(ROOT, "build", "app", "gradmesh"))
STRAY = os.environ.get("STRAY_PIXELS", os.path.join(ROOT, "build", "bench", "stray_pixels"))
IMAGES = ["fruits.jpg", "HappyFish.jpg", "astronaut.png", "smarties.png", "opencv-logo.png",
          "detect_blob.png", "thin_lines.png"]
# Our points: (--max-error, --total-patches or None). The error targets alone give the middle
# and the top of our curve (3 alone is convert's default); whole-image budgets give its low end.
# Budget 0 draws every region flat (no mesh): the low end, where a tracer's small files lie;
# E 40 there coarsens the outlines further.
OUR_POINTS = [(40, 0), (20, 0), (8, 0), (3, 0), (2, 100), (2, 300), (2, 1000), (2, 3000), (2, 6000),
              (2, 12000), (8, None), (6, None), (4, None), (3, None), (2, None)]
DEFAULT_POINT = (3, None)
TRACERS = [("vtracer", p) for p in ["coarse", "photo", "default", "detailed"]] + \
          [("imagetracer", p) for p in ["posterized2", "smoothed", "default", "detailed"]]


def run(args, **kwargs):
    return subprocess.run(args, check=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, **kwargs)


def install_tracers():
    modules = os.path.join(OUT, "npm", "node_modules")
    if not os.path.isdir(os.path.join(modules, "@neplex", "vectorizer")) or \
            not os.path.isdir(os.path.join(modules, "imagetracerjs")):
        os.makedirs(os.path.join(OUT, "npm"), exist_ok=True)
        run(["npm", "install", "--prefix", os.path.join(OUT, "npm"), "--no-save",
             "@neplex/vectorizer", "imagetracerjs"])
    return modules


def image_size(path):
    info = run(["oiiotool", "--info", path]).stdout
    size = info.split(":")[1].split(",")[0].split("x")
    return int(size[0]), int(size[1]), "4 channel" in info


def flatten(name):
    """The image as an RGB PNG over white, and its size."""
    source = os.path.join(ROOT, "samples", name)
    flat = os.path.join(OUT, "inputs", os.path.splitext(name)[0] + ".png")
    os.makedirs(os.path.dirname(flat), exist_ok=True)
    width, height, has_alpha = image_size(source)
    if has_alpha:
        run(["oiiotool", source, "--pattern", "constant:color=1,1,1,1",
             f"{width}x{height}", "4", "--over", "--ch", "R,G,B", "-d", "uint8", "-o", flat])
    else:
        run(["oiiotool", source, "--ch", "R,G,B", "-d", "uint8", "-o", flat])
    return flat, width, height


def score(image, svg, width, height):
    """Inkscape's render of the SVG against the image, and the file's bytes."""
    png = svg[:-4] + "_inkscape.png"
    env = dict(os.environ, HOME=os.path.join(OUT, "inkscape-home"))
    run(["inkscape", "--export-type=png", f"--export-filename={png}",
         f"--export-width={width}", f"--export-height={height}", svg], env=env)
    figures = json.loads(run([STRAY, image, png, "--map", svg[:-4] + "_stray.png"]).stdout)
    data = open(svg, "rb").read()
    figures.update(bytes=len(data), gzip=len(gzip.compress(data, 9)))
    return figures


def our_points(image, stem, width, height):
    points = []
    for error, total in OUR_POINTS:
        budgeted = total is not None
        name = f"E {error}" + (f", {total} patches" if budgeted else "")
        gmb = os.path.join(OUT, f"{stem}_gm_e{error}" + (f"_t{total}" if budgeted else "") + ".gmb")
        budget = ["--total-patches", str(total)] if budgeted else []
        run([GM, "convert", image, "--segment", "--max-error", str(error), *budget, "-o", gmb])
        patches = int(run([GM, "info", gmb]).stdout.split("patches:")[1].split()[0])
        svg = gmb[:-4] + ".svg"
        bare = gmb[:-4] + "_noscript.svg"
        run([GM, "convert", gmb, "-o", svg])
        run([GM, "convert", gmb, "--svg-script", "none", "-o", bare])
        figures = score(image, svg, width, height)
        data = open(bare, "rb").read()
        figures.update(tool="gradmesh", preset=name, patches=patches,
                       bytes_noscript=len(data), gzip_noscript=len(gzip.compress(data, 9)),
                       default=(error, total) == DEFAULT_POINT)
        points.append(figures)
    return points


def tracer_points(modules, image, stem, width, height):
    points = []
    for tool, preset in TRACERS:
        svg = os.path.join(OUT, f"{stem}_{tool}_{preset}.svg")
        run(["node", os.path.join(ROOT, "bench", "tracers.mjs"), modules, tool, preset, image, svg])
        figures = score(image, svg, width, height)
        figures.update(tool=tool, preset=preset)
        points.append(figures)
    return points


def interpolate(curve, x_key, y_key, x, log_y):
    """y at x on the curve (x rising), linear in x, log y if asked; None outside the curve."""
    ordered = sorted(curve, key=lambda p: p[x_key])
    for a, b in zip(ordered, ordered[1:]):
        if a[x_key] <= x <= b[x_key] and b[x_key] > a[x_key]:
            t = (x - a[x_key]) / (b[x_key] - a[x_key])
            if log_y:
                return math.exp(math.log(a[y_key]) + t * (math.log(b[y_key]) - math.log(a[y_key])))
            return a[y_key] + t * (b[y_key] - a[y_key])
    return None


def smallest_at_least(ours, key, psnr):
    """The fewest bytes (key) among our points of at least this PSNR; None if none reaches it."""
    sizes = [p[key] for p in ours if p["psnr"] >= psnr]
    return min(sizes) if sizes else None


def front(points, key):
    """The points no other point beats: none has at least their PSNR in fewer bytes (key). A
    user picks the setting that gives the best file, so the curve runs through these only."""
    return [p for p in points
            if not any(q[key] <= p[key] and q["psnr"] >= p["psnr"] and
                       (q[key] < p[key] or q["psnr"] > p["psnr"]) for q in points)]


def compare(ours, theirs):
    """Our bytes at each tracer point's PSNR (ratios) and our PSNR at its bytes, on the front of
    our points (raw and gzipped bytes each their own). Where the tracer's PSNR lies below our
    whole curve, the ratio is bounded by our smallest file that reaches it (`bound`: "at
    most")."""
    rows = []
    raw_front, gzip_front = front(ours, "bytes"), front(ours, "gzip")
    for point in theirs:
        raw = interpolate(raw_front, "psnr", "bytes", point["psnr"], True)
        zipped = interpolate(gzip_front, "psnr", "gzip", point["psnr"], True)
        psnr_raw = interpolate(raw_front, "bytes", "psnr", point["bytes"], False)
        bound_raw = smallest_at_least(ours, "bytes", point["psnr"])
        bound_gzip = smallest_at_least(ours, "gzip", point["psnr"])
        rows.append(dict(tool=point["tool"], preset=point["preset"],
                         ratio=raw / point["bytes"] if raw else None,
                         ratio_gzip=zipped / point["gzip"] if zipped else None,
                         bound=bound_raw / point["bytes"] if bound_raw else None,
                         bound_gzip=bound_gzip / point["gzip"] if bound_gzip else None,
                         our_psnr_at_bytes=psnr_raw))
    return rows


def fmt(value, pattern):
    return "—" if value is None else pattern.format(value)


def ratio_cell(value, bound):
    """The interpolated ratio, else "≤" our smallest file's that reaches the PSNR."""
    if value is not None:
        return f"{value:.2f}"
    return "—" if bound is None else f"≤ {bound:.2f}"


def print_image(name, ours, theirs, comparison):
    print(f"\n### {name}\n")
    print("| tool | setting | patches | SVG B | gzip B | E | PSNR | stray px |")
    print("|---|---|---|---|---|---|---|---|")
    for p in sorted(ours + theirs, key=lambda p: (p["tool"], p["bytes"])):
        setting = p["preset"] + (" (default)" if p.get("default") else "")
        bytes_cell = f"{p['bytes']:,}"
        if "bytes_noscript" in p:
            bytes_cell += f" ({p['bytes_noscript']:,} no script)"
        print(f"| {p['tool']} | {setting} | {p.get('patches', '')} | {bytes_cell} | "
              f"{p['gzip']:,} | {p['E']:.2f} | {p['psnr']:.2f} | {p['stray']} |")
    print("\n| tracer point | our bytes at its PSNR / its bytes (raw, gzip) | our PSNR at its bytes |")
    print("|---|---|---|")
    for row in comparison:
        print(f"| {row['tool']} {row['preset']} | {ratio_cell(row['ratio'], row.get('bound'))}, "
              f"{ratio_cell(row['ratio_gzip'], row.get('bound_gzip'))} | "
              f"{fmt(row['our_psnr_at_bytes'], '{:.2f}')} |")


def reprint(path):
    """The tables again from a results.json, the ratios computed anew."""
    with open(path) as f:
        results = json.load(f)
    for name, r in results.items():
        print_image(name, r["ours"], r["tracers"], compare(r["ours"], r["tracers"]))


def main():
    if sys.argv[1:2] == ["--from"]:
        reprint(sys.argv[2])
        return
    names = sys.argv[1:] or IMAGES
    modules = install_tracers()
    results = {}
    for name in names:
        image, width, height = flatten(name)
        stem = os.path.splitext(name)[0]
        ours = our_points(image, stem, width, height)
        theirs = tracer_points(modules, image, stem, width, height)
        comparison = compare(ours, theirs)
        results[name] = dict(ours=ours, tracers=theirs, comparison=comparison)
        print_image(name, ours, theirs, comparison)
        sys.stdout.flush()
    with open(os.path.join(OUT, "results.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
