#include "flat_backdrop.h"

#include <cmath>
#include <deque>
#include <set>
#include <utility>

#include "converters/regions.h"

namespace gm {

bool coloursWithin(const Vec3& a, const Vec3& b, double tolerance) {
    for (int c = 0; c < 3; ++c)
        if (std::fabs(a[c] - b[c]) > tolerance) return false;
    return true;
}

void joinPixels(Region& into, const Region& from) {
    for (size_t p = 0; p < into.mask.size(); ++p)
        if (from.mask[p] && !into.mask[p]) {
            into.mask[p] = 1;
            ++into.pixelCount;
        }
}

size_t mergeIntoBackdrop(std::vector<Region>& regions, size_t firstInk,
                         const std::vector<Vec3>& colours, double tolerance) {
    if (regions.size() < 2) return 0;
    const auto mergeable = [&](int k) {
        return k > 0 && static_cast<size_t>(k) < firstInk && coloursWithin(colours[k], colours[0], tolerance);
    };
    // The regions reached from the first through mergeable ones.
    const std::vector<std::set<int>> neighbours = touchingRegions(regions);
    std::vector<char> merged(regions.size(), 0);
    std::deque<int> queue{0};
    while (!queue.empty()) {
        const int k = queue.front();
        queue.pop_front();
        for (int n : neighbours[static_cast<size_t>(k)])
            if (!merged[static_cast<size_t>(n)] && mergeable(n)) {
                merged[static_cast<size_t>(n)] = 1;
                queue.push_back(n);
            }
    }
    size_t count = 0;
    std::vector<Region> kept;
    for (size_t k = 0; k < regions.size(); ++k) {
        if (!merged[k]) {
            kept.push_back(std::move(regions[k]));
            continue;
        }
        joinPixels(kept.front(), regions[k]);
        ++count;
    }
    regions = std::move(kept);
    return count;
}

}  // namespace gm
