// OpenCV reports a failed allocation as a cv::Exception (cv::Error::StsNoMem), not as
// std::bad_alloc, which is what the commands report as "out of memory" (and what ends a
// whole-image conversion rather than one region's attempt).
#pragma once

#include <opencv2/core.hpp>

#include <new>

namespace gm {

// f(), with an OpenCV allocation failure inside it rethrown as std::bad_alloc.
template <class F>
auto withOpenCvOutOfMemoryAsBadAlloc(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const cv::Exception& e) {
        if (e.code == cv::Error::StsNoMem) throw std::bad_alloc();
        throw;
    }
}

}  // namespace gm
