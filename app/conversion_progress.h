// The progress line of convert and render (terminal_line.h): the stage, the regions done of
// their total where the converter counts them, and the seconds so far. It appears once the run
// has lasted a second, is redrawn a few times a second by a thread of its own (a long stage
// sends no news) and is erased at the end.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "converters/convert_image.h"
#include "terminal_line.h"

namespace gm {

class ConversionProgress {
public:
    explicit ConversionProgress(std::string label);  // "convert horse.png"
    ~ConversionProgress();
    ConversionProgress(const ConversionProgress&) = delete;
    ConversionProgress& operator=(const ConversionProgress&) = delete;

    // A stage of the command's own (read, mask, write); its count is cleared.
    void stage(const char* name);
    // What ConvertOptions::progress gets: any thread may call it, at any time.
    std::function<void(const ConvertProgress&)> callback();

private:
    void update(const ConvertProgress& p);
    void drawUntilStopped();
    std::string text();

    std::string label_;
    TerminalLine line_;
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable stop_;
    bool stopping_ = false;
    std::string stage_;
    int done_ = 0, total_ = 0;
    std::thread drawer_;
};

}  // namespace gm
