#include "view_mesh_lines.h"

#include <cmath>
#include <cstdio>

#include "meshcore/bezier_patch.h"

namespace gm {

namespace {

// Writes path data in tenths of a pixel, relative to the last point written, so that long
// runs of edges stay short and rounding does not accumulate.
class PathWriter {
public:
    explicit PathWriter(std::string& out) : out_(out) {}

    // The edge p0..p3; starts a new run unless p0 is where the last edge ended.
    void edge(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3) {
        const long x0 = tenths(p0.x), y0 = tenths(p0.y);
        if (!open_ || x0 != x_ || y0 != y_) {
            out_ += 'M';
            number(x0);
            number(y0);
            x_ = x0;
            y_ = y0;
            open_ = true;
            // Each run starts with its own 'c' after the moveto.
            needCommand_ = true;
        }
        if (needCommand_) out_ += 'c';
        needCommand_ = false;
        for (const Vec2* p : {&p1, &p2}) {
            number(tenths(p->x) - x_);
            number(tenths(p->y) - y_);
        }
        const long x3 = tenths(p3.x), y3 = tenths(p3.y);
        number(x3 - x_);
        number(y3 - y_);
        x_ = x3;
        y_ = y3;
    }

private:
    static long tenths(double v) { return std::lround(v * 10.0); }

    // "12.3", "-.4", "5": separated by a space unless the sign separates it.
    void number(long tenthsValue) {
        const bool negative = tenthsValue < 0;
        const long a = negative ? -tenthsValue : tenthsValue;
        char text[32];
        if (a % 10 == 0)
            std::snprintf(text, sizeof text, "%ld", a / 10);
        else if (a < 10)
            std::snprintf(text, sizeof text, ".%ld", a);
        else
            std::snprintf(text, sizeof text, "%ld.%ld", a / 10, a % 10);
        const char last = out_.empty() ? 'M' : out_.back();
        if (negative)
            out_ += '-';
        else if (last != 'M' && last != 'c')
            out_ += ' ';
        out_ += text;
    }

    std::string& out_;
    long x_ = 0, y_ = 0;
    bool open_ = false;
    bool needCommand_ = true;
};

// Edge of a Bézier patch: along s (a varies) at row b, or along t (b varies) at column a.
void alongS(PathWriter& w, const BezierPatch& p, int b) {
    w.edge(p.p[0][b], p.p[1][b], p.p[2][b], p.p[3][b]);
}
void alongT(PathWriter& w, const BezierPatch& p, int a) {
    w.edge(p.p[a][0], p.p[a][1], p.p[a][2], p.p[a][3]);
}

bool slitBelow(const GradientMesh& m, int i, int j) {
    for (const Slit& s : m.slits)
        if (j + 1 == s.row && i >= s.i0 && i < s.i1) return true;
    return false;
}

void meshLines(PathWriter& w, const GradientMesh& m) {
    const int C = m.columns(), R = m.rows();
    // Horizontal runs: the top edge of each patch row, the bottom of the last row and the
    // upper side of each slit.
    for (int j = 0; j < R; ++j) {
        for (int i = 0; i < C; ++i) alongS(w, toBezier(m, i, j), 0);
        for (int i = 0; i < C; ++i)
            if (j == R - 1 || slitBelow(m, i, j)) alongS(w, toBezier(m, i, j), 3);
    }
    // Vertical runs: the left edge of each patch column and the right of the last column.
    for (int i = 0; i < C; ++i)
        for (int j = 0; j < R; ++j) alongT(w, toBezier(m, i, j), 0);
    for (int j = 0; j < R; ++j) alongT(w, toBezier(m, C - 1, j), 3);
}

}  // namespace

std::string meshLinesPathData(const Document& doc) {
    std::string out;
    PathWriter writer(out);
    for (const GradientMesh& m : doc.meshes) meshLines(writer, m);
    return out;
}

}  // namespace gm
