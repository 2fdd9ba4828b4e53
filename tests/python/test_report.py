"""Document.report: the figures of `convert --report R.json`, as a dict."""

import json

import pytest

import gradmesh
from conftest import FAST, FAST_ARGS, run_cli


def keys(value, prefix=""):
    """Every key path of a JSON value (lists by their first element)."""
    if isinstance(value, dict):
        out = set()
        for k, v in value.items():
            out |= {prefix + k} | keys(v, prefix + k + ".")
        return out
    if isinstance(value, list) and value:
        return keys(value[0], prefix + "[].")
    return set()


def test_report_has_the_cli_report_keys_and_figures(tmp_path, apple):
    image, mask = apple
    report = tmp_path / "cli.json"
    code, err = run_cli("convert", image, "--mask", mask, *FAST_ARGS, "-o", tmp_path / "cli.gmb",
                        "--report", report)
    assert code == 0, err
    expected = json.loads(report.read_text())
    doc = gradmesh.convert(image, mask=mask, **FAST)
    got = doc.report
    assert isinstance(got, dict)
    assert keys(got) == keys(expected)
    assert got["output"] is None and got["bytes"]["output"] is None
    for key in ("width", "height", "patches", "meshes", "colors", "max_error", "max_patches"):
        assert got[key] == expected[key], key
    assert got["error"] == expected["error"]
    for key in ("gmb_lossless", "gmb_compact", "svg"):
        assert got["bytes"][key] == expected["bytes"][key], key
    assert got["patches"] == doc.patches
    assert got["compact"]["level"] == 0
    assert got is doc.report  # computed once


def test_loaded_document_has_no_report(tmp_path, apple):
    image, mask = apple
    gradmesh.convert(image, mask=mask, **FAST).save(tmp_path / "a.gmb")
    assert gradmesh.load(tmp_path / "a.gmb").report is None
