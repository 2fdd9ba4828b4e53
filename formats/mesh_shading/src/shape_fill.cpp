// Flat shapes as filled or stroked paths in PDF and PostScript (mesh_shading.h).
#include <cmath>

#include "formats/mesh_shading.h"

namespace gm {

const PathOperators kPdfPathOperators{"rg", "m", "l",       "c", "h",  "f",
                                      "RG", "w", "1 J 1 j", "S", "W n"};
const PathOperators kPostScriptPathOperators{
    "setrgbcolor", "moveto",       "lineto",
    "curveto",     "closepath",    "fill",
    "setrgbcolor", "setlinewidth", "1 setlinecap 1 setlinejoin",
    "stroke",      "clip newpath"};

namespace {

constexpr size_t kLineLength = 200;

bool isLine(Vec2 a, Vec2 h1, Vec2 h2, Vec2 b) {
    const double tol = 5e-4;
    const Vec2 e1 = h1 - (a + (1.0 / 3) * (b - a)), e2 = h2 - (a + (2.0 / 3) * (b - a));
    return std::fabs(e1.x) <= tol && std::fabs(e1.y) <= tol && std::fabs(e2.x) <= tol &&
           std::fabs(e2.y) <= tol;
}

class OperatorText {
public:
    explicit OperatorText(std::string& out) : out_(out), lineStart_(out.size()) {}
    void point(Vec2 p) {
        word(formatDecimal(p.x, 3));
        word(formatDecimal(p.y, 3));
    }
    void word(const std::string& w) {
        if (out_.size() - lineStart_ + w.size() + 1 > kLineLength) {
            out_ += '\n';
            lineStart_ = out_.size();
        } else if (out_.size() > lineStart_) {
            out_ += ' ';
        }
        out_ += w;
    }
    void endLine() {
        out_ += '\n';
        lineStart_ = out_.size();
    }

private:
    std::string& out_;
    size_t lineStart_;
};

void colour(OperatorText& text, Vec3 col, const char* setColor) {
    for (int c = 0; c < 3; ++c) text.word(formatDecimal(std::fmin(1.0, std::fmax(0.0, col[c])), 4));
    text.word(setColor);
}

// One path of 3n + 1 points: its segments from the first point; a closed one's last segment,
// when a line, left to the close (unless it is a centreline's only one: a filled outline of one
// segment encloses nothing).
void centreline(OperatorText& text, const std::vector<Vec2>& path, const PathOperators& ops,
                bool closed, bool fillable = false) {
    const size_t last = path.size() - 1;
    text.point(path[0]);
    text.word(ops.moveTo);
    for (size_t k = 0; k < last; k += 3) {
        const Vec2 a = path[k], h1 = path[k + 1], h2 = path[k + 2], b = path[k + 3];
        if (isLine(a, h1, h2, b)) {
            if (closed && k + 3 == last && (k > 0 || fillable)) break;  // the close draws it
            text.point(b);
            text.word(ops.lineTo);
        } else {
            text.point(h1);
            text.point(h2);
            text.point(b);
            text.word(ops.curveTo);
        }
    }
    if (closed) text.word(ops.close);
}

// A filled shape's subpaths, each moved to and closed.
void outline(OperatorText& text, const FlatShape& shape, const PathOperators& ops) {
    for (std::vector<Vec2> path : shape.subpaths) {
        path.push_back(path.front());  // an outline closes implicitly
        centreline(text, path, ops, true, true);
    }
}

}  // namespace

std::string shapeFillOperators(const FlatShape& shape, const PathOperators& ops) {
    std::string out;
    OperatorText text(out);
    colour(text, shape.col, ops.setColor);
    outline(text, shape, ops);
    text.word(ops.fill);
    text.endLine();
    return out;
}

std::string shapeClipOperators(const FlatShape& shape, const PathOperators& ops) {
    std::string out;
    OperatorText text(out);
    outline(text, shape, ops);
    text.word(ops.clip);
    text.endLine();
    return out;
}

std::string shapeStrokeOperators(const FlatShape& shape, const PathOperators& ops) {
    std::string out;
    OperatorText text(out);
    colour(text, shape.col, ops.setStrokeColor);
    text.word(formatDecimal(std::fmax(shape.strokeWidth, 1e-3), 3));  // 0 would be a hairline
    text.word(ops.setLineWidth);
    text.word(ops.roundCapsJoins);
    for (const std::vector<Vec2>& path : shape.subpaths)
        centreline(text, path, ops, path.back() == path.front());
    text.word(ops.stroke);
    text.endLine();
    return out;
}

}  // namespace gm
