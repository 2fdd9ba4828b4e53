#include "svg_tensor_effect.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

Vec2 coonsInterior(const Vec2 (&q)[4][4], bool mirrorU, bool mirrorV) {
    auto at = [&](int a, int b) -> Vec2 {
        return q[mirrorU ? 3 - a : a][mirrorV ? 3 - b : b];
    };
    return (1.0 / 9) * (-4.0 * at(0, 0) + 6.0 * (at(1, 0) + at(0, 1)) -
                        2.0 * (at(3, 0) + at(0, 3)) + 3.0 * (at(1, 3) + at(3, 1)) - at(3, 3));
}

namespace {

void bernstein(double t, double (&b)[4], double (&db)[4]) {
    const double s = 1 - t;
    b[0] = s * s * s, b[1] = 3 * t * s * s, b[2] = 3 * t * t * s, b[3] = t * t * t;
    db[0] = -3 * s * s, db[1] = 3 * s * s - 6 * t * s, db[2] = 6 * t * s - 3 * t * t,
    db[3] = 3 * t * t;
}

struct NetPoint {
    Vec2 p, du, dv;
};

NetPoint evaluate(const Vec2 (&q)[4][4], double u, double v) {
    double bu[4], dbu[4], bv[4], dbv[4];
    bernstein(u, bu, dbu);
    bernstein(v, bv, dbv);
    NetPoint r{};
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            r.p = r.p + (bu[a] * bv[b]) * q[a][b];
            r.du = r.du + (dbu[a] * bv[b]) * q[a][b];
            r.dv = r.dv + (bu[a] * dbv[b]) * q[a][b];
        }
    return r;
}

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

}  // namespace

double tensorColorEffect(const Vec2 (&withTensor)[4][4], const Vec3 (&cornerColor)[4]) {
    Vec2 coons[4][4];
    std::copy(&withTensor[0][0], &withTensor[0][0] + 16, &coons[0][0]);
    coons[1][1] = coonsInterior(withTensor, false, false);
    coons[2][1] = coonsInterior(withTensor, true, false);
    coons[2][2] = coonsInterior(withTensor, true, true);
    coons[1][2] = coonsInterior(withTensor, false, true);
    const Vec3 &c00 = cornerColor[0], &c10 = cornerColor[1], &c11 = cornerColor[2],
               &c01 = cornerColor[3];
    constexpr int kSamples = 6;  // per direction, inside the patch
    double sign = 0, largest = 0;
    for (int i = 1; i < kSamples; ++i)
        for (int j = 1; j < kSamples; ++j) {
            const double u = double(i) / kSamples, v = double(j) / kSamples;
            const NetPoint drawn = evaluate(coons, u, v);
            const double det = cross(drawn.du, drawn.dv);
            if (!(std::fabs(det) > 1e-9) || det * sign < 0)
                return std::numeric_limits<double>::infinity();
            sign = det;
            const Vec2 moved = evaluate(withTensor, u, v).p - drawn.p;
            // The parameter step that reaches the intended point on the drawn patch.
            const double du = cross(moved, drawn.dv) / det, dv = cross(drawn.du, moved) / det;
            for (int k = 0; k < 3; ++k) {
                const double cu = (1 - v) * (c10[k] - c00[k]) + v * (c11[k] - c01[k]);
                const double cv = (1 - u) * (c01[k] - c00[k]) + u * (c11[k] - c10[k]);
                largest = std::max(largest, std::fabs(cu * du + cv * dv));
            }
        }
    return largest;
}

}  // namespace gm
