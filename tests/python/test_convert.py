"""gradmesh.convert from paths and arrays gives the CLI's files, byte for byte."""

import numpy as np
import pytest

import gradmesh
from conftest import FAST, FAST_ARGS, SAMPLES, run_cli


def cli_file(tmp_path, name, *args):
    out = tmp_path / name
    code, err = run_cli("convert", *args, "-o", out)
    assert code == 0, err
    return out.read_bytes()


@pytest.fixture(scope="module")
def apple_doc():
    image, mask = SAMPLES / "apple.jpg", SAMPLES / "apple_mask.png"
    return gradmesh.convert(image, mask=mask, **FAST)


def test_gmb_from_paths_is_the_cli_file(tmp_path, apple, apple_doc):
    image, mask = apple
    expected = cli_file(tmp_path, "cli.gmb", image, "--mask", mask, *FAST_ARGS)
    written = apple_doc.save(tmp_path / "py.gmb")
    assert written == len(expected)
    assert (tmp_path / "py.gmb").read_bytes() == expected


def test_compact_gmb_is_refitted_as_the_cli_does(tmp_path, apple, apple_doc):
    image, mask = apple
    expected = cli_file(tmp_path, "cli.gmb", image, "--mask", mask, *FAST_ARGS, "--compact-level", "2")
    apple_doc.save(tmp_path / "py.gmb", compact_level=2)
    assert (tmp_path / "py.gmb").read_bytes() == expected
    # Without the image to refit against, the compact file would differ.
    assert apple_doc.encode(".gmb", compact=True) != apple_doc.encode(".gmb")


@pytest.mark.parametrize("ext,args,options", [
    (".svg", [], {}),
    (".svg", ["--svg-colors", "exact", "--svg-script", "none"], {"svg_colors": "exact", "svg_script": "none"}),
    (".eps", [], {}),
    (".pdf", ["--text-shading"], {"text_shading": True}),
    (".png", ["--scale", "0.5", "--background", "white"], {"scale": 0.5, "background": "white"}),
])
def test_other_formats_are_the_cli_files(tmp_path, apple, apple_doc, ext, args, options):
    image, mask = apple
    expected = cli_file(tmp_path, "cli" + ext, image, "--mask", mask, *FAST_ARGS, *args)
    apple_doc.save(tmp_path / ("py" + ext), **options)
    assert (tmp_path / ("py" + ext)).read_bytes() == expected


def test_hermite_svg_is_refitted_as_the_cli_does(tmp_path, apple):
    image, mask = apple
    expected = cli_file(tmp_path, "cli.svg", image, "--mask", mask, *FAST_ARGS, "--colors", "hermite")
    doc = gradmesh.convert(str(image), mask=str(mask), colors="hermite", **FAST)
    doc.save(tmp_path / "py.svg")
    assert (tmp_path / "py.svg").read_bytes() == expected


def test_arrays_convert_as_their_files(tmp_path, apple, apple_doc):
    image, mask = apple
    expected = apple_doc.encode(".gmb")
    pixels = gradmesh.read_image(image)
    assert pixels.dtype == np.float32 and pixels.ndim == 3 and pixels.shape[2] == 4
    mask_bool = gradmesh.read_image(mask)[:, :, 0] >= 0.5
    from_float = gradmesh.convert(pixels, mask=mask_bool, **FAST)
    assert from_float.encode(".gmb") == expected
    # 8-bit samples as the JPEG holds them, in Fortran order and as a strided RGB view.
    rgb8 = np.round(pixels[:, :, :3] * 255).astype(np.uint8)
    assert gradmesh.convert(np.asfortranarray(rgb8), mask=mask_bool, **FAST).encode(".gmb") == expected
    padded = np.zeros(rgb8.shape[:2] + (5,), np.uint8)
    padded[:, :, 1:4] = rgb8
    view = padded[:, :, 1:4]
    assert not view.flags.c_contiguous
    assert gradmesh.convert(view, mask=mask_bool.astype(np.uint8) * 255, **FAST).encode(".gmb") == expected


def test_a_different_image_gives_a_different_file(apple, apple_doc):
    image, mask = apple
    pixels = gradmesh.read_image(image)
    pixels[100:200, 100:200, :3] = 0
    doc = gradmesh.convert(pixels, mask=mask, **FAST)
    assert doc.encode(".gmb") != apple_doc.encode(".gmb")


def test_grey_alpha_array_is_its_rgba_array():
    grey = np.zeros((96, 128), np.float64)
    grey[:, 30:100] = np.linspace(0.2, 0.9, 70)
    alpha = np.zeros((96, 128), np.float64)
    alpha[20:70, 30:100] = 1
    grey_alpha = np.stack([grey, alpha], axis=-1)
    rgba = np.stack([grey, grey, grey, alpha], axis=-1).astype(np.float32)
    doc = gradmesh.convert(grey_alpha, max_patches=20)
    assert (doc.width, doc.height, doc.meshes) == (128, 96, 1)
    assert 1 <= doc.patches <= 20
    assert doc.encode(".gmb") == gradmesh.convert(rgba, max_patches=20).encode(".gmb")


def test_segment_is_the_cli_file(tmp_path):
    image = SAMPLES / "HappyFish.jpg"
    args = ["--segment", "--segments", "6", "--max-patches", "40", "--threads", "2"]
    expected = cli_file(tmp_path, "cli.gmb", image, *args)
    doc = gradmesh.convert(image, segment=True, segments=6, max_patches=40, threads=2)
    assert doc.encode(".gmb") == expected
    assert doc.meshes > 1


def test_segment_switches_are_the_cli_flags(tmp_path):
    # A flat trace without gradients or strokes, and a mesh conversion without residue shapes:
    # the same files as --total-patches 0 --no-gradients --no-strokes and --no-residue.
    image = SAMPLES / "HappyFish.jpg"
    flat = ["--segment", "--total-patches", "0", "--max-error", "8", "--threads", "2"]
    expected = cli_file(tmp_path, "flat.gmb", image, *flat, "--no-gradients", "--no-strokes")
    doc = gradmesh.convert(image, segment=True, total_patches=0, max_error=8, threads=2,
                           gradients=False, strokes=False)
    assert doc.encode(".gmb") == expected
    assert doc.patches == 0
    meshes = ["--segment", "--segments", "6", "--max-patches", "40", "--threads", "2"]
    expected = cli_file(tmp_path, "bare.gmb", image, *meshes, "--no-residue")
    doc = gradmesh.convert(image, segment=True, segments=6, max_patches=40, threads=2,
                           residue=False)
    assert doc.encode(".gmb") == expected
