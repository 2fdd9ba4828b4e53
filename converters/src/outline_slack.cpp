// Room for a flat shape's outline beneath later regions (outline_slack.h), from two distance
// transforms.
#include "outline_slack.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace gm {

namespace {

// Per pixel, the distance (px, between centres) to the nearest pixel where `target` holds;
// a large number when there is none.
cv::Mat distanceTo(const std::vector<uint8_t>& target, int w, int h) {
    cv::Mat free(h, w, CV_8U);
    bool any = false;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool t = target[static_cast<size_t>(y) * w + x] != 0;
            free.at<uint8_t>(y, x) = t ? 0 : 255;
            any = any || t;
        }
    cv::Mat distance;
    if (!any) return cv::Mat(h, w, CV_32F, cv::Scalar(1e6f));
    cv::distanceTransform(free, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    return distance;
}

}  // namespace

double OutlineSlack::at(Vec2 p) const {
    const int x = static_cast<int>(std::floor(p.x)), y = static_cast<int>(std::floor(p.y));
    if (room.empty() || x < 0 || y < 0 || x >= width || y >= height) return 0;
    return room[static_cast<size_t>(y) * width + x];
}

OutlineSlack hiddenOutlineSlack(const std::vector<uint8_t>& own, const std::vector<uint8_t>& under,
                                int w, int h, double reach, double margin) {
    OutlineSlack slack;
    slack.width = w, slack.height = h;
    const size_t n = static_cast<size_t>(w) * h;
    std::vector<uint8_t> keep(n), shown(n);
    for (size_t k = 0; k < n; ++k) {
        keep[k] = !own[k] && !under[k];
        shown[k] = own[k] && !under[k];
    }
    const cv::Mat toKeep = distanceTo(keep, w, h), toShown = distanceTo(shown, w, h);
    slack.room.assign(n, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double d = std::min(toKeep.at<float>(y, x), toShown.at<float>(y, x)) - margin;
            slack.room[static_cast<size_t>(y) * w + x] =
                static_cast<float>(std::clamp(d, 0.0, reach));
        }
    return slack;
}

}  // namespace gm
