"""gradmesh.load reads .gmb and .svg; documents round-trip through files and pickle."""

import pickle

import numpy as np

import gradmesh
from conftest import FAST, run_cli


def test_gmb_round_trip(tmp_path, apple):
    image, mask = apple
    doc = gradmesh.convert(image, mask=mask, **FAST)
    doc.save(tmp_path / "a.gmb")
    loaded = gradmesh.load(tmp_path / "a.gmb")
    assert (loaded.width, loaded.height, loaded.meshes, loaded.patches) == \
        (doc.width, doc.height, doc.meshes, doc.patches)
    assert loaded.encode(".gmb") == (tmp_path / "a.gmb").read_bytes()
    assert np.array_equal(loaded.render(), doc.render())


def test_files_are_read_as_the_cli_reads_them(tmp_path):
    for name in ("sample.gmb", "sample.svg"):
        code, err = run_cli("sample", tmp_path / name)
        assert code == 0, err
    doc = gradmesh.load(str(tmp_path / "sample.gmb"))
    assert (doc.width, doc.height, doc.meshes, doc.holes) == (512, 512, 2, 3)
    assert doc.encode(".gmb") == (tmp_path / "sample.gmb").read_bytes()
    # The SVG holds the holed mesh as hole-free pieces: read back as the CLI reads it.
    sample = tmp_path / "sample.svg"
    code, err = run_cli("convert", sample, "-o", tmp_path / "cli.gmb")
    assert code == 0, err
    doc = gradmesh.load(sample)
    assert doc.meshes > 2 and doc.holes == 0
    doc.save(tmp_path / "py.gmb")
    assert (tmp_path / "py.gmb").read_bytes() == (tmp_path / "cli.gmb").read_bytes()


def test_pickle_keeps_meshes_and_report(apple):
    image, mask = apple
    doc = gradmesh.convert(image, mask=mask, **FAST)
    copy = pickle.loads(pickle.dumps(doc))
    assert copy.encode(".gmb") == doc.encode(".gmb")
    assert copy.report == doc.report
    assert repr(copy) == repr(doc) and "patches" in repr(doc)
