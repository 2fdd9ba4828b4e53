// Test support: comparing our render with a consumer's, and running external programs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sys/wait.h>
#include <string>
#include <vector>

#include "meshcore/image.h"

namespace gmtest {

struct DiffStats {
    double mean = 0, max = 0;  // 0–255 units, over RGB channels of compared pixels
    size_t count = 0;          // compared pixels
};

// Compares RGB over the interior of `ours`: pixels whose alpha is 1 and whose neighbours within
// erodePx (Chebyshev distance) all have alpha 1, so that outline anti-aliasing, which differs
// between renderers, is left out. Both images must have the same size and be opaque where
// compared (composite over a background first).
inline DiffStats compareInterior(const gm::RgbaImage& ours, const gm::RgbaImage& theirs,
                                 int erodePx = 1) {
    DiffStats d;
    if (ours.width != theirs.width || ours.height != theirs.height) {
        d.max = 1e9;
        return d;
    }
    const int W = ours.width, H = ours.height;
    std::vector<unsigned char> solid(static_cast<size_t>(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) solid[static_cast<size_t>(y) * W + x] = ours.at(x, y)[3] >= 0.999f;
    double sum = 0;
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            bool inside = true;
            for (int dy = -erodePx; dy <= erodePx && inside; ++dy)
                for (int dx = -erodePx; dx <= erodePx && inside; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    inside = xx >= 0 && yy >= 0 && xx < W && yy < H &&
                             solid[static_cast<size_t>(yy) * W + xx];
                }
            if (!inside) continue;
            for (int c = 0; c < 3; ++c) {
                const double e = std::fabs(double(ours.at(x, y)[c]) - theirs.at(x, y)[c]) * 255.0;
                sum += e;
                d.max = std::max(d.max, e);
            }
            ++d.count;
        }
    }
    d.mean = d.count ? sum / (3.0 * d.count) : 0;
    return d;
}

// Runs a shell command; returns its exit status (-1 when it could not be run).
inline int runCommand(const std::string& command) {
    const int rc = std::system(command.c_str());
    if (rc == -1) return -1;
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Shell-quotes a path.
inline std::string quote(const std::string& s) {
    std::string out = "'";
    for (char ch : s) out += (ch == '\'') ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

}  // namespace gmtest
