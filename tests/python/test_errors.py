"""Failures raise Python exceptions with the CLI's messages; nothing is half-written."""

import os

import numpy as np
import pytest

import gradmesh
from conftest import FAST, SAMPLES, cli_message


def test_missing_input_has_the_cli_message(tmp_path):
    missing = tmp_path / "nosuch.png"
    expected = cli_message("convert", missing, "-o", tmp_path / "out.gmb")
    with pytest.raises(gradmesh.Error) as caught:
        gradmesh.convert(missing)
    assert str(caught.value) == expected
    assert caught.value.file == str(missing)
    assert isinstance(caught.value, RuntimeError)


def test_damaged_image_has_the_cli_message(tmp_path):
    bad = tmp_path / "bad.png"
    bad.write_bytes((SAMPLES / "pic1.png").read_bytes()[:300])
    expected = cli_message("convert", bad, "-o", tmp_path / "out.gmb")
    with pytest.raises(gradmesh.Error) as caught:
        gradmesh.convert(bad)
    assert str(caught.value) == expected


def test_mask_of_another_size_names_the_mask(tmp_path, apple):
    image, _ = apple
    other = SAMPLES / "pic1.png"
    expected = cli_message("convert", image, "--mask", other, "-o", tmp_path / "out.gmb")
    with pytest.raises(gradmesh.Error) as caught:
        gradmesh.convert(image, mask=other)
    assert str(caught.value) == expected
    with pytest.raises(gradmesh.Error, match="<mask array>"):
        gradmesh.convert(image, mask=np.ones((5, 5), bool))


def test_load_errors_have_the_cli_messages(tmp_path, apple):
    image, _ = apple
    expected = cli_message("render", image, "-o", tmp_path / "out.png")
    with pytest.raises(gradmesh.Error) as caught:
        gradmesh.load(image)
    assert str(caught.value) == expected
    garbage = tmp_path / "garbage.gmb"
    garbage.write_bytes(b"GMB1" + b"\xff" * 40)
    expected = cli_message("render", garbage, "-o", tmp_path / "out.png")
    with pytest.raises(gradmesh.Error) as caught:
        gradmesh.load(garbage)
    assert str(caught.value) == expected


@pytest.mark.parametrize("shape,dtype,message", [
    ((10,), np.uint8, r"image must be an HxW, HxWx1, HxWx2, HxWx3 or HxWx4 array, got shape \(10,\)"),
    ((10, 10, 5), np.uint8, r"got shape \(10, 10, 5\)"),
    ((0, 10, 3), np.uint8, r"image is empty"),
    ((10, 10, 3), np.int32, r"image must be uint8, uint16, bool, float32 or float64, got int32"),
])
def test_bad_arrays_are_value_errors(shape, dtype, message):
    with pytest.raises(ValueError, match=message):
        gradmesh.convert(np.zeros(shape, dtype))


def test_not_an_image_is_a_type_error():
    with pytest.raises(TypeError, match="image must be a path or a NumPy array, got object"):
        gradmesh.convert(object())


def test_unknown_options_are_type_errors(apple):
    image, mask = apple
    with pytest.raises(TypeError, match="convert\\(\\) got an unexpected keyword argument 'max_eror'"):
        gradmesh.convert(image, mask=mask, max_eror=3)
    doc = gradmesh.convert(image, mask=mask, **FAST)
    with pytest.raises(TypeError, match="save\\(\\) got an unexpected keyword argument 'compressed'"):
        doc.save("x.gmb", compressed=True)


@pytest.mark.parametrize("options,message", [
    ({"max_error": 300}, "max_error expects a number from 0 to 255, got 300"),
    ({"max_patches": "many"}, "max_patches expects a number from 1 to 1e[+]?0?6, got 'many'"),
    ({"colors": "rgb"}, "colors expects bicubic, hermite or sampled, got 'rgb'"),
    ({"segment": 1}, "segment expects True or False, got 1"),
    ({"segments": 5}, "segments needs segment=True"),
    ({"residue": False}, "residue needs segment=True"),
    ({"segment": True, "gradients": "no"}, "gradients expects True or False, got 'no'"),
    ({"segment": True, "mask": "m.png"}, "segment=True converts the whole image; it takes no mask"),
])
def test_bad_values_are_value_errors(apple, options, message):
    image, _ = apple
    options = dict(options)
    mask = options.pop("mask", None)
    with pytest.raises(ValueError, match=message):
        gradmesh.convert(image, mask=mask, **options)


def test_save_errors_have_the_cli_messages_and_write_nothing(tmp_path, apple):
    image, mask = apple
    doc = gradmesh.convert(image, mask=mask, **FAST)
    expected = cli_message("convert", image, "--mask", mask, *[], "-o", tmp_path / "out.xyz")
    with pytest.raises(gradmesh.Error) as caught:
        doc.save(tmp_path / "out.xyz")
    assert str(caught.value) == expected
    with pytest.raises(gradmesh.Error, match="the output's directory does not exist"):
        doc.save(tmp_path / "no" / "out.gmb")
    # The document's own inputs are never overwritten.
    copy = tmp_path / "mask.png"
    copy.write_bytes(mask.read_bytes())
    doc = gradmesh.convert(image, mask=copy, **FAST)
    with pytest.raises(gradmesh.Error, match="refusing to overwrite it"):
        doc.save(copy)
    assert copy.read_bytes() == mask.read_bytes()
    with pytest.raises(ValueError, match="compact_level expects a whole number from 0 to 6"):
        doc.save(tmp_path / "a.gmb", compact_level=9)
    assert sorted(os.listdir(tmp_path)) == ["mask.png"]
