#include "conversion_progress.h"

#include <cstdio>

namespace gm {

namespace {

constexpr auto kQuietStart = std::chrono::seconds(1);      // runs shorter than this show nothing
constexpr auto kRedraw = std::chrono::milliseconds(200);

}  // namespace

ConversionProgress::ConversionProgress(std::string label)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()) {
    if (line_.enabled()) drawer_ = std::thread([this] { drawUntilStopped(); });
}

ConversionProgress::~ConversionProgress() {
    if (!drawer_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    stop_.notify_all();
    drawer_.join();
    line_.erase();
}

void ConversionProgress::stage(const char* name) {
    std::lock_guard<std::mutex> lock(mutex_);
    stage_ = name;
    done_ = total_ = 0;
}

std::function<void(const ConvertProgress&)> ConversionProgress::callback() {
    if (!line_.enabled()) return nullptr;  // nothing to draw: the converter need not call
    return [this](const ConvertProgress& p) { update(p); };
}

void ConversionProgress::update(const ConvertProgress& p) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (p.total > 0) {
        // Regions finish in any order on several threads: the count only grows.
        if (p.total != total_ || p.done > done_) done_ = p.done;
        total_ = p.total;
    }
    stage_ = p.stage;
}

std::string ConversionProgress::text() {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, ", %.0f s", elapsed);
    std::string t = "gradmesh " + label_ + ": " + stage_;
    if (total_ > 0)
        t += (stage_ == "regions" ? " " : ", regions ") + std::to_string(done_) + "/" +
             std::to_string(total_);
    return t + seconds;
}

void ConversionProgress::drawUntilStopped() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (stop_.wait_until(lock, start_ + kQuietStart, [this] { return stopping_; })) return;
    std::string shown;
    while (!stopping_) {
        if (std::string now = text(); now != shown) line_.show(shown = now);
        stop_.wait_for(lock, kRedraw, [this] { return stopping_; });
    }
}

}  // namespace gm
