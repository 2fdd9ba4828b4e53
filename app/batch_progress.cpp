#include "batch_progress.h"

#include <cstdio>
#include <string>

namespace gm {

namespace {

std::string durationText(double seconds) {
    const long s = static_cast<long>(seconds + 0.5);
    char buf[32];
    if (s >= 3600) std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, s / 60 % 60);
    else if (s >= 60) std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%lds", s);
    return buf;
}

}  // namespace

BatchProgress::BatchProgress(int total, int skipped)
    : total_(total), skipped_(skipped),
      start_(std::chrono::steady_clock::now()) {
    redraw();
}

void BatchProgress::imageDone(bool ok) {
    ++done_;
    failed_ += ok ? 0 : 1;
    redraw();
}

void BatchProgress::redraw() {
    if (!line_.enabled()) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double rate = elapsed > 0 ? done_ / elapsed : 0;
    std::string line = "batch: " + std::to_string(done_) + "/" + std::to_string(total_) + " images";
    if (failed_) line += ", " + std::to_string(failed_) + " failed";
    if (skipped_) line += ", " + std::to_string(skipped_) + " already done";
    char figures[96];
    if (done_ > 0) {
        std::snprintf(figures, sizeof figures, ", %.2f images/s, ETA %s", rate,
                      durationText((total_ - done_) / rate).c_str());
        line += figures;
    }
    line += ", " + durationText(elapsed) + " elapsed";
    line_.show(line);
}

void BatchProgress::finish() {
    redraw();
    line_.keep();
}

}  // namespace gm
