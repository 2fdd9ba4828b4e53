// Batch's progress line on a terminal: images done of the total, failures, images per second
// and the time left. Nothing at all when stderr is not a terminal (terminal_line.h).
#pragma once

#include <chrono>

#include "terminal_line.h"

namespace gm {

class BatchProgress {
public:
    // `total`: the images this run converts (those skipped as done are not counted).
    BatchProgress(int total, int skipped);
    void imageDone(bool ok);
    void redraw();  // the rate and time left move on between images
    void finish();

private:
    TerminalLine line_;
    int total_, skipped_, done_ = 0, failed_ = 0;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace gm
