"""The GIL is released while the library works: other Python threads run meanwhile."""

import threading

import gradmesh
from conftest import FAST


def count_while(work):
    """Runs work() in a thread; returns how often this thread got round its loop meanwhile."""
    thread = threading.Thread(target=work)
    thread.start()
    count = 0
    while thread.is_alive():
        count += 1
    thread.join()
    return count


def test_conversion_and_render_release_the_gil(apple):
    image, mask = apple
    result = {}

    def convert():
        result["doc"] = gradmesh.convert(image, mask=mask, **FAST)
        result["pixels"] = result["doc"].render(scale=4)

    # Holding the GIL, the conversion would leave this thread a few switch intervals at most.
    assert count_while(convert) > 100000
    assert result["pixels"].shape[0] == 4 * result["doc"].height
