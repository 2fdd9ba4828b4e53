// What the full-size line finders (segment_thin.h, segment_ink.h) look at around a pixel: the
// pairs of pixels on either side of it along a row, a column or a diagonal.
#pragma once

#include <opencv2/core.hpp>

namespace gm {

// Calls visit(a, b) for every pair of pixels of `bgr` (8-bit BGR) a >= 1 steps before and b >= 1
// after (x, y), a + b <= maxSpan, along each of the four directions, both inside the image.
template <class Visit>
void forEachSidePair(const cv::Mat& bgr, int x, int y, int maxSpan, Visit visit) {
    static const int kDirs[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    for (const auto& d : kDirs)
        for (int a = 1; a < maxSpan; ++a)
            for (int b = 1; a + b <= maxSpan; ++b) {
                const int xa = x - a * d[0], ya = y - a * d[1], xb = x + b * d[0], yb = y + b * d[1];
                if (xa < 0 || ya < 0 || ya >= bgr.rows || xb >= bgr.cols || yb < 0 ||
                    yb >= bgr.rows)
                    continue;
                visit(bgr.at<cv::Vec3b>(ya, xa), bgr.at<cv::Vec3b>(yb, xb));
            }
}

}  // namespace gm
