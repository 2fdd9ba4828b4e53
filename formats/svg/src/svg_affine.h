// An SVG affine transform (the matrix(a b c d e f) of transform and gradientTransform).
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

struct SvgAffine {
    double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;  // x' = a x + c y + e, y' = b x + d y + f
    Vec2 apply(Vec2 p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
    // The linear part alone (a direction, not a point).
    Vec2 applyLinear(Vec2 v) const { return {a * v.x + c * v.y, b * v.x + d * v.y}; }
    double determinant() const { return a * d - b * c; }
};

// t ∘ m: first m, then t.
inline SvgAffine compose(const SvgAffine& t, const SvgAffine& m) {
    SvgAffine r;
    r.a = t.a * m.a + t.c * m.b;
    r.b = t.b * m.a + t.d * m.b;
    r.c = t.a * m.c + t.c * m.d;
    r.d = t.b * m.c + t.d * m.d;
    r.e = t.a * m.e + t.c * m.f + t.e;
    r.f = t.b * m.e + t.d * m.f + t.f;
    return r;
}

}  // namespace gm
