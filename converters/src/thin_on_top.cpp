// Thin flat regions drawn last (thin_on_top.h).
#include "thin_on_top.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>

#include "converters/regions.h"
#include "flat_backdrop.h"

namespace gm {

double regionThickness(const Region& region) {
    const int w = region.width, h = region.height;
    const PixelBox box = maskBounds(region.mask, w, h);
    if (box.empty()) return 0;
    // A frame of background around the box, so that the border of the image bounds nothing.
    cv::Mat mask = cv::Mat::zeros(box.y1 - box.y0 + 3, box.x1 - box.x0 + 3, CV_8U);
    for (int y = box.y0; y <= box.y1; ++y)
        for (int x = box.x0; x <= box.x1; ++x)
            if (region.mask[static_cast<size_t>(y) * w + x])
                mask.at<uint8_t>(y - box.y0 + 1, x - box.x0 + 1) = 255;
    cv::Mat distance;
    cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    double deepest = 0;
    cv::minMaxLoc(distance, nullptr, &deepest);
    return std::max(1.0, 2 * deepest - 1);
}

size_t liftThinRegions(std::vector<Region>& regions, size_t firstInk,
                       const std::vector<char>& thin) {
    firstInk = std::min(firstInk, regions.size());
    std::vector<Region> lifted;
    std::vector<Region> kept;
    for (size_t k = 0; k < firstInk; ++k)
        (thin[k] ? lifted : kept).push_back(std::move(regions[k]));
    const size_t firstThin = kept.size();
    for (size_t k = 0; k < lifted.size(); ++k) regions[firstThin + k] = std::move(lifted[k]);
    for (size_t k = 0; k < firstThin; ++k) regions[k] = std::move(kept[k]);
    return firstThin;
}

size_t mergeAcrossThin(std::vector<Region>& regions, size_t firstThin, size_t& firstInk,
                       const std::vector<char>& flat, const std::vector<Vec3>& colours,
                       double tolerance) {
    const size_t lastThin = regions.size();
    if (firstThin >= lastThin || regions.size() < 3) return 0;
    const std::vector<std::set<int>> neighbours = touchingRegions(regions);
    // into[k]: the region k merges into (itself when none).
    std::vector<size_t> into(regions.size());
    for (size_t k = 0; k < into.size(); ++k) into[k] = k;
    for (size_t t = firstThin; t < lastThin; ++t) {
        std::vector<size_t> beside;
        for (int n : neighbours[t])
            if (static_cast<size_t>(n) < firstThin && flat[static_cast<size_t>(n)])
                beside.push_back(static_cast<size_t>(n));
        std::sort(beside.begin(), beside.end());
        for (size_t b = 0; b < beside.size(); ++b)
            for (size_t a = 0; a < b; ++a) {
                const size_t k = beside[b];
                if (into[k] == k && coloursWithin(colours[k], colours[beside[a]], tolerance))
                    into[k] = beside[a];
            }
    }
    // Thin regions of one colour that touch: the pieces a segmentation cut one line into.
    for (size_t t = firstThin + 1; t < lastThin; ++t)
        for (int n : neighbours[t]) {
            const size_t a = static_cast<size_t>(n);
            if (a >= firstThin && a < t && into[t] == t && flat[a] && flat[t] &&
                coloursWithin(colours[t], colours[a], tolerance))
                into[t] = a;
        }
    size_t count = 0, mergedBeforeInk = 0;
    std::vector<Region> kept;
    std::vector<size_t> keptAt(regions.size());
    for (size_t k = 0; k < regions.size(); ++k) {
        if (into[k] == k) {
            keptAt[k] = kept.size();
            kept.push_back(std::move(regions[k]));
            continue;
        }
        mergedBeforeInk += k < firstInk;
        size_t root = into[k];
        while (into[root] != root) root = into[root];  // into[] points to earlier regions
        joinPixels(kept[keptAt[root]], regions[k]);
        ++count;
    }
    regions = std::move(kept);
    firstInk -= mergedBeforeInk;
    return count;
}

}  // namespace gm
