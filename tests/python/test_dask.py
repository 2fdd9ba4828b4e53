"""The Dask recipe of docs/python.md: images converted on a LocalCluster of two worker
processes give the files a conversion in this process gives."""

import pytest

import gradmesh
from conftest import SAMPLES

distributed = pytest.importorskip("distributed")

# Debian 12's tornado warns about its own event-loop set-up under distributed.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

# (image, mask, options): small budgets, one thread per conversion (the workers are the
# parallelism).
JOBS = [
    ("apple.jpg", "apple_mask.png", {"max_patches": 60, "max_error": 6}),
    ("horse.png", None, {"max_patches": 40, "max_error": 8}),
    ("HappyFish.jpg", None, {"segment": True, "segments": 4, "max_patches": 30}),
    ("pic1.png", None, {"max_patches": 40, "max_error": 8}),
]


def convert_to_file(image, mask, options, out):
    """What each worker runs: convert, write, hand back the report's figures."""
    doc = gradmesh.convert(image, mask=mask, threads=1, **options)
    doc.save(out)
    return {"patches": doc.patches, "psnr": doc.report["error"]["psnr"]}


def test_local_cluster_converts_as_this_process_does(tmp_path):
    jobs = [(str(SAMPLES / image), mask and str(SAMPLES / mask), options,
             str(tmp_path / (image.split(".")[0] + ".gmb"))) for image, mask, options in JOBS]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        futures = [client.submit(convert_to_file, *job, pure=False) for job in jobs]
        results = client.gather(futures)
        # A Document itself comes back through pickle.
        remote = client.submit(gradmesh.convert, jobs[0][0], mask=jobs[0][1], threads=1,
                               **jobs[0][2]).result()
        workers = {w for w in client.who_has(futures).values() for w in w}
    assert len(workers) == 2, "both workers took jobs"
    for (image, mask, options, out), result in zip(jobs, results):
        local = gradmesh.convert(image, mask=mask, threads=1, **options)
        assert open(out, "rb").read() == local.encode(".gmb"), image
        assert result["patches"] == local.patches
    assert remote.encode(".gmb") == open(jobs[0][3], "rb").read()
    assert remote.report["patches"] == results[0]["patches"]
