// Flat shapes as filled paths in PDF and PostScript (mesh_shading.h).
#include <cmath>

#include "formats/mesh_shading.h"

namespace gm {

const PathOperators kPdfPathOperators{"rg", "m", "l", "c", "h", "f"};
const PathOperators kPostScriptPathOperators{"setrgbcolor", "moveto",    "lineto",
                                             "curveto",     "closepath", "fill"};

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

}  // namespace

std::string shapeFillOperators(const FlatShape& shape, const PathOperators& ops) {
    std::string out;
    OperatorText text(out);
    for (int c = 0; c < 3; ++c)
        text.word(formatDecimal(std::fmin(1.0, std::fmax(0.0, shape.col[c])), 4));
    text.word(ops.setColor);
    for (const std::vector<Vec2>& path : shape.subpaths) {
        const size_t n = path.size();
        text.point(path[0]);
        text.word(ops.moveTo);
        for (size_t k = 0; k < n; k += 3) {
            const Vec2 a = path[k], h1 = path[k + 1], h2 = path[k + 2], b = path[(k + 3) % n];
            if (isLine(a, h1, h2, b)) {
                if (k + 3 >= n) break;  // closing the path draws it
                text.point(b);
                text.word(ops.lineTo);
            } else {
                text.point(h1);
                text.point(h2);
                text.point(b);
                text.word(ops.curveTo);
            }
        }
        text.word(ops.close);
    }
    text.word(ops.fill);
    text.endLine();
    return out;
}

}  // namespace gm
