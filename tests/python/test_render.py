"""Document.render: shape, dtype, no copy, and the CLI's render pixel for pixel."""

import numpy as np
import pytest

import gradmesh
from conftest import FAST, SAMPLES, run_cli


@pytest.fixture(scope="module")
def apple_doc():
    image, mask = SAMPLES / "apple.jpg", SAMPLES / "apple_mask.png"
    return gradmesh.convert(image, mask=mask, **FAST)


def test_float_render_shape_and_ownership(apple_doc):
    pixels = apple_doc.render()
    assert pixels.dtype == np.float32
    assert pixels.shape == (apple_doc.height, apple_doc.width, 4)
    assert pixels.flags.c_contiguous and pixels.flags.writeable
    # The renderer's own buffer, kept alive by the array (no copy was made).
    assert not pixels.flags.owndata and pixels.base is not None
    alpha = pixels[:, :, 3]
    assert alpha.max() == pytest.approx(1.0) and alpha.min() == 0.0
    twice = apple_doc.render(scale=2)
    assert twice.shape == (2 * apple_doc.height, 2 * apple_doc.width, 4)


@pytest.mark.parametrize("args,options", [
    ([], {}),
    (["--scale", "1.5", "--background", "#336699"], {"scale": 1.5, "background": "#336699"}),
    (["--mesh-lines", "#ff0000"], {"mesh_lines": (1.0, 0.0, 0.0)}),
])
def test_uint8_render_is_the_cli_png(tmp_path, apple_doc, args, options):
    gmb = tmp_path / "apple.gmb"
    apple_doc.save(gmb)
    png = tmp_path / "cli.png"
    code, err = run_cli("render", gmb, "-o", png, *args)
    assert code == 0, err
    expected = np.round(gradmesh.read_image(png) * 255).astype(np.uint8)
    pixels = apple_doc.render(dtype="uint8", **options)
    assert pixels.dtype == np.uint8
    assert pixels.shape == expected.shape
    assert np.array_equal(pixels, expected)


def test_float_render_rounds_to_the_uint8_render(apple_doc):
    floats = apple_doc.render()
    bytes_ = apple_doc.render(dtype="uint8")
    assert np.abs(np.clip(floats, 0, 1) * 255 - bytes_).max() <= 0.5 + 1e-3


def test_background_makes_it_opaque(apple_doc):
    pixels = apple_doc.render(background="white")
    assert pixels[:, :, 3].min() == pytest.approx(1.0)
    assert np.allclose(pixels[0, 0, :3], 1.0)


def test_render_options_are_checked(apple_doc):
    with pytest.raises(ValueError, match="scale expects a number from 0.01 to 64"):
        apple_doc.render(scale=0)
    with pytest.raises(ValueError, match="dtype expects 'float32' or 'uint8'"):
        apple_doc.render(dtype="float64")
    with pytest.raises(ValueError, match="background expects"):
        apple_doc.render(background="#12")
