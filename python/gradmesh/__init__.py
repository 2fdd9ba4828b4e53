"""gradmesh: raster images to topology-preserving gradient meshes (docs/python.md).

    import gradmesh
    doc = gradmesh.convert("apple.jpg", mask="apple_mask.png", max_error=2)
    doc.save("apple.svg")
    pixels = doc.render(scale=2)          # H x W x 4 float32, straight alpha
    print(doc.patches, doc.report["error"])

The options are the keyword forms of `gradmesh convert`'s (docs/cli.md): --max-error is
max_error, --segment is segment=True. Failures with inputs and outputs raise gradmesh.Error
with the CLI's message; bad options raise TypeError (unknown keyword) or ValueError.
"""

import os

from ._gradmesh import MAX_DOCUMENT_PATCHES, MAX_PIXELS, Document, Error
from ._gradmesh import _convert, _load, _read_image

__all__ = ["Document", "Error", "convert", "load", "read_image"]


def _path_or_array(value):
    """A str path for str, bytes and os.PathLike; anything else is left to be an array."""
    if isinstance(value, (str, bytes, os.PathLike)):
        return os.fsdecode(os.fspath(value))
    return value


def convert(source, mask=None, **options):
    """Converts an image (a path or a NumPy array) to gradient meshes; returns a Document.

    source: an image file (.png .jpg .tif .exr ...) or an array: H x W grey, H x W x 1..4
      (grey, grey+alpha, RGB, RGBA), uint8, uint16, bool, float32 or float64 (0-1), any strides.
    mask: the object mask, a file or an H x W array (white / non-zero = object); else the alpha
      channel, else foreground extraction (as `gradmesh convert`).
    options: max_error, max_patches, colors ("bicubic", "hermite", "sampled"), segment,
      segments, min_region, total_patches (0: a flat trace), strokes, gradients, residue (each
      True unless set False, with segment=True), min_area, min_hole, samples, threads,
      max_pixels, max_document_patches.
    """
    return _convert(_path_or_array(source), _path_or_array(mask), options)


def load(path, max_document_patches=MAX_DOCUMENT_PATCHES):
    """Reads a mesh file (.gmb, or an .svg with meshes) as `gradmesh convert` reads it."""
    return _load(_path_or_array(path), max_document_patches)


def read_image(path, max_pixels=MAX_PIXELS):
    """An image file as convert reads it: H x W x 4 float32, straight alpha, sRGB 0-1."""
    return _read_image(_path_or_array(path), max_pixels)


def _save(self, path, **options):
    """Writes the document in the format of path's extension (.gmb .svg .svgz .eps .pdf .png
    .jpg .tif .exr), as `gradmesh convert` writes it: whole or not at all, never over the
    files it was made from. Options: compact, compact_level (0-6 or "auto"), legacy,
    svg_colors, svg_script, svg_fallback, color_tolerance, min_piece, text_shading, scale,
    background, mesh_lines, max_output_bytes. Returns the bytes written."""
    return self._save(_path_or_array(path), options)


def _encode(self, name, **options):
    """The bytes save(name) would write, without writing: name's extension picks the format
    (".gmb", "x.svg", ...)."""
    name = _path_or_array(name)
    if name.startswith(".") and os.sep not in name:
        name = "document" + name
    return self._encode(name, options)


def _render(self, scale=1.0, background=None, mesh_lines=None, dtype="float32"):
    """The document rendered as `gradmesh render` renders it: an H x W x 4 array (H, W the
    canvas times scale), straight alpha, sRGB. dtype "float32" (the default: the renderer's own
    buffer, no copy; colours not clamped) or "uint8" (clamped and rounded as the PNG writer
    does). background and mesh_lines: "#rrggbb[aa]", "white", "black", "none" or (r, g, b[, a])."""
    return self._render({"scale": scale, "background": background, "mesh_lines": mesh_lines,
                         "dtype": dtype})


Document.save = _save
Document.encode = _encode
Document.render = _render
