// Flat shapes as SVG paths (svg_shapes.h).
#include "svg_shapes.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "svg_number.h"

namespace gm {

namespace {

constexpr double kSteps = 100;  // 1/100 px, the compact mesh syntax's precision
constexpr int kDecimals = kSvgDecimalsCompact;

struct StepPoint {
    long long x = 0, y = 0;
};
StepPoint steps(Vec2 p) { return {std::llround(p.x * kSteps), std::llround(p.y * kSteps)}; }
StepPoint operator-(StepPoint a, StepPoint b) { return {a.x - b.x, a.y - b.y}; }
StepPoint operator+(StepPoint a, StepPoint b) { return {a.x + b.x, a.y + b.y}; }

// Path data with separators only where the grammar needs them and command letters only where
// the command changes (a repeated command may be left out, except after a moveto, whose
// repetitions would be linetos).
class PathText {
public:
    explicit PathText(std::string& out) : out_(out) {}

    void command(char letter) {
        if (letter == last_ && letter != 'm' && letter != 'M') return;
        out_ += letter;
        last_ = letter;
        afterLetter_ = true;
    }
    void point(StepPoint p) {
        number(p.x);
        number(p.y);
    }
    void number(long long v) {
        text_.clear();
        appendSvgNumber(text_, static_cast<double>(v) / kSteps, true, kDecimals);
        const bool joins = text_[0] == '-' || (text_[0] == '.' && previousHasPoint_);
        if (!afterLetter_ && !joins) out_ += ' ';
        out_ += text_;
        previousHasPoint_ = text_.find('.') != std::string::npos;
        afterLetter_ = false;
    }

private:
    std::string& out_;
    std::string text_;
    char last_ = 0;
    bool afterLetter_ = true, previousHasPoint_ = false;
};

bool isLine(StepPoint a, StepPoint h1, StepPoint h2, StepPoint b) {
    auto near = [](StepPoint h, StepPoint a, StepPoint b, double t) {
        return std::fabs(h.x - (a.x + t * (b.x - a.x))) <= 1 &&
               std::fabs(h.y - (a.y + t * (b.y - a.y))) <= 1;
    };
    return near(h1, a, b, 1.0 / 3) && near(h2, a, b, 2.0 / 3);
}

// Whether step b continues step a in the same direction (so one line can draw both).
bool continues(StepPoint a, StepPoint b) {
    return a.x * b.y == a.y * b.x && a.x * b.x + a.y * b.y > 0;
}

// A line by `step`: h or v along an axis, else l.
void appendLine(PathText& text, StepPoint step) {
    if (step.y == 0 || step.x == 0) {
        text.command(step.y == 0 ? 'h' : 'v');
        text.number(step.y == 0 ? step.x : step.y);
        return;
    }
    text.command('l');
    text.point(step);
}

// Writes the lines and cubics of segments [0, segments) of `path` (segment m from path[3m] via
// path[3m+1], path[3m+2] to path[(3m+3) % size]), from the current point `at`: straight ones
// as lines, consecutive ones in one direction merged, zero-length ones left out. The last run
// of lines is left in `run` (the caller writes it or lets z draw it); false when nothing was
// written nor left.
bool appendSegments(PathText& text, const std::vector<Vec2>& path, size_t segments, StepPoint& at,
                    StepPoint& run) {
    const size_t n = path.size();
    bool drawn = false;
    for (size_t k = 0; k < 3 * segments; k += 3) {
        const StepPoint a = steps(path[k]), h1 = steps(path[k + 1]), h2 = steps(path[k + 2]);
        const StepPoint b = steps(path[(k + 3) % n]);
        if (isLine(a, h1, h2, b)) {
            const StepPoint step = b - a;
            if (step.x == 0 && step.y == 0) continue;
            if ((run.x != 0 || run.y != 0) && !continues(run, step)) {
                appendLine(text, run);
                at = at + run;
                run = {};
            }
            run = run + step;
            drawn = true;
            continue;
        }
        if (run.x != 0 || run.y != 0) {
            appendLine(text, run);
            at = at + run;
            run = {};
        }
        text.command('c');
        text.point(h1 - at);
        text.point(h2 - at);
        text.point(b - at);
        at = b;
        drawn = true;
    }
    return drawn;
}

// Starts a subpath at `start`: absolute for the document's first, else relative.
void appendMove(PathText& text, StepPoint start, StepPoint current, bool first) {
    if (first) {
        text.command('M');
        text.point(start);
    } else {
        text.command('m');
        text.point(start - current);
    }
}

// One closed subpath (a cycle of cubics), the closing run of lines left to z.
void appendSubpath(PathText& text, const std::vector<Vec2>& path, StepPoint& current, bool first) {
    const StepPoint start = steps(path[0]);
    appendMove(text, start, current, first);
    StepPoint at = start, run;
    appendSegments(text, path, path.size() / 3, at, run);
    text.command('z');  // draws the run of lines left, which ends at the start
    current = start;  // after z the current point is the subpath's start
}

// One centreline (3n + 1 points): closed ones end in z as a closed subpath does, open ones
// with their last run of lines. One whose segments all round to nothing is a dot, written as
// a line of length 0 (round caps paint it; a lone moveto would paint nothing).
void appendCentreline(PathText& text, const std::vector<Vec2>& path, StepPoint& current,
                      bool first) {
    const StepPoint start = steps(path[0]);
    appendMove(text, start, current, first);
    StepPoint at = start, run;
    if (!appendSegments(text, path, (path.size() - 1) / 3, at, run)) {
        text.command('h');
        text.number(0);
        current = start;
        return;
    }
    if (path.back() == path.front()) {
        text.command('z');
        current = start;
        return;
    }
    if (run.x != 0 || run.y != 0) {
        appendLine(text, run);
        at = at + run;
    }
    current = at;
}

// The d attribute's text of a stroked shape's centrelines.
void appendCentrelinePathData(std::string& out, const std::vector<std::vector<Vec2>>& subpaths) {
    PathText text(out);
    StepPoint current;
    bool first = true;
    for (const std::vector<Vec2>& path : subpaths) {
        if (path.size() < 4) continue;
        appendCentreline(text, path, current, first);
        first = false;
    }
}

// ` name="alpha"`, e.g. fill-opacity.
void appendOpacity(std::string& out, const char* name, double alpha) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", std::fmin(1.0, std::fmax(0.0, alpha)));
    out += ' ';
    out += name;
    out += "=\"";
    out += text;
    out += '"';
}

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// Parses path data into subpaths; a small state machine over commands and their numbers.
// `centrelines`: subpaths in the layout of a stroked shape, else closed cycles.
class PathParser {
public:
    PathParser(const std::string& d, double maxCoordinate, size_t maxPoints, bool centrelines)
        : p_(d.c_str()),
          maxCoordinate_(maxCoordinate),
          maxPoints_(maxPoints),
          centrelines_(centrelines) {}

    bool run(std::vector<std::vector<Vec2>>& subpaths, std::string& problem) {
        char cmd = 0;
        while (true) {
            skipSeparators();
            if (!*p_) break;
            if (std::isalpha(static_cast<unsigned char>(*p_))) {
                cmd = *p_++;
                if (std::strchr("MmLlHhVvCcZz", cmd) == nullptr)
                    return fail(problem, std::string("unsupported path command '") + cmd + "'");
                if (cmd == 'Z' || cmd == 'z') {
                    end(true);
                    continue;
                }
            } else if (cmd == 0 || cmd == 'Z' || cmd == 'z') {
                return fail(problem, "path data does not start with a command");
            }
            if (!segment(cmd, problem)) return false;
            if (cmd == 'M') cmd = 'L';  // implicit repetitions of a moveto are linetos
            if (cmd == 'm') cmd = 'l';
        }
        end(false);
        subpaths = std::move(done_);
        return true;
    }

private:
    bool fail(std::string& problem, const std::string& what) {
        problem = what;
        return false;
    }

    void skipSeparators() {
        while (*p_ && (std::isspace(static_cast<unsigned char>(*p_)) || *p_ == ',')) ++p_;
    }

    bool number(double& v, std::string& problem) {
        skipSeparators();
        const char c0 = *p_;
        if (!(std::isdigit(static_cast<unsigned char>(c0)) || c0 == '-' || c0 == '+' || c0 == '.'))
            return fail(problem, "a number is missing in path data");
        char* end = nullptr;
        v = std::strtod(p_, &end);
        if (end == p_) return fail(problem, "malformed number in path data");
        for (const char* q = p_; q < end; ++q)
            if (std::isalpha(static_cast<unsigned char>(*q)) && *q != 'e' && *q != 'E')
                return fail(problem, "malformed number in path data");
        if (!std::isfinite(v) || std::fabs(v) > maxCoordinate_)
            return fail(problem, "number out of range in path data");
        p_ = end;
        return true;
    }

    bool point(Vec2& q, bool relative, std::string& problem) {
        if (!number(q.x, problem) || !number(q.y, problem)) return false;
        if (relative) q = q + current_;
        return true;
    }

    bool segment(char cmd, std::string& problem) {
        const bool rel = std::islower(static_cast<unsigned char>(cmd)) != 0;
        const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(cmd)));
        Vec2 a, b, e;
        if (c == 'M') {
            if (!point(e, rel, problem)) return false;
            end(false);
            current_ = start_ = e;
            return true;
        }
        if (c == 'H' || c == 'V') {
            double v = 0;
            if (!number(v, problem)) return false;
            e = current_;
            (c == 'H' ? e.x : e.y) = rel ? (c == 'H' ? current_.x : current_.y) + v : v;
            return line(e, problem);
        }
        if (c == 'L') return point(e, rel, problem) && line(e, problem);
        if (!point(a, rel, problem) || !point(b, rel, problem) || !point(e, rel, problem))
            return false;
        return cubic(a, b, e, problem);
    }

    bool line(Vec2 e, std::string& problem) {
        const Vec2 s = current_;
        return cubic(s + (1.0 / 3) * (e - s), s + (2.0 / 3) * (e - s), e, problem);
    }

    bool cubic(Vec2 a, Vec2 b, Vec2 e, std::string& problem) {
        if (open_.empty()) open_.push_back(current_);
        open_.insert(open_.end(), {a, b, e});
        current_ = e;
        if ((points_ += 3) > maxPoints_) return fail(problem, "path data has too many points");
        return true;
    }

    // Ends the open subpath, by z (`closed`) or not. Filled subpaths always close: the last
    // point closes onto the first (a line added when they differ). A centreline closes only by
    // z, ending exactly on its first point (a line added when it ends elsewhere); else it stays
    // open. A subpath without segments is dropped.
    void end(bool closed) {
        if (open_.size() >= 4 && (closed || !centrelines_)) {
            const Vec2 s = open_.front(), last = open_.back();
            // Relative coordinates add up to the start only up to rounding.
            const double tol = 1e-7 * (1 + std::fabs(s.x) + std::fabs(s.y));
            if (std::fabs(last.x - s.x) <= tol && std::fabs(last.y - s.y) <= tol) {
                open_.pop_back();
            } else {
                open_.insert(open_.end(),
                             {last + (1.0 / 3) * (s - last), last + (2.0 / 3) * (s - last)});
            }
            if (centrelines_) open_.push_back(s);
        }
        if (open_.size() >= 4) done_.push_back(std::move(open_));
        open_.clear();
        current_ = start_;
    }

    const char* p_;
    const double maxCoordinate_;
    const size_t maxPoints_;
    const bool centrelines_;
    size_t points_ = 0;
    Vec2 current_, start_;
    std::vector<Vec2> open_;
    std::vector<std::vector<Vec2>> done_;
};

}  // namespace

void appendHexColour(std::string& out, Vec3 col) {
    static const char* hex = "0123456789abcdef";
    out += '#';
    for (int k = 0; k < 3; ++k) {
        const long v = std::lround(std::fmin(1.0, std::fmax(0.0, col[k])) * 255.0);
        out += hex[v >> 4];
        out += hex[v & 15];
    }
}

void appendShapePath(std::string& out, const FlatShape& shape, SvgGradientWriter& gradients) {
    if (shape.stroked()) {
        out += "<path fill=\"none\" stroke=\"";
        appendHexColour(out, shape.col);
        out += '"';
        if (shape.alpha < 1) appendOpacity(out, "stroke-opacity", shape.alpha);
        // Never 0, which would paint nothing: the narrowest stroke written is 0.01 px.
        out += " stroke-width=\"";
        appendSvgNumber(out, std::fmax(shape.strokeWidth, 0.01), false, kDecimals);
        out += "\" stroke-linecap=\"round\" stroke-linejoin=\"round\" d=\"";
        appendCentrelinePathData(out, shape.subpaths);
        out += "\"/>\n";
        return;
    }
    if (shape.graded()) {
        const std::string id = gradients.append(out, shape.gradient);
        out += "<path fill=\"url(#" + id + ")\"";
    } else {
        out += "<path fill=\"";
        appendHexColour(out, shape.col);
        out += '"';
    }
    if (shape.alpha < 1) appendOpacity(out, "fill-opacity", shape.alpha);
    out += " d=\"";
    appendClosedPathData(out, shape.subpaths);
    out += "\"/>\n";
}

void appendClosedPathData(std::string& out, const std::vector<std::vector<Vec2>>& subpaths) {
    PathText text(out);
    StepPoint current;
    bool first = true;
    for (const std::vector<Vec2>& path : subpaths) {
        if (path.size() < 3) continue;
        appendSubpath(text, path, current, first);
        first = false;
    }
}

bool parseShapePathData(const std::string& d, double maxCoordinate, size_t maxPoints,
                        std::vector<std::vector<Vec2>>& subpaths, std::string& problem) {
    return PathParser(d, maxCoordinate, maxPoints, false).run(subpaths, problem);
}

bool parseCentrelinePathData(const std::string& d, double maxCoordinate, size_t maxPoints,
                             std::vector<std::vector<Vec2>>& subpaths, std::string& problem) {
    return PathParser(d, maxCoordinate, maxPoints, true).run(subpaths, problem);
}

bool parseHexColour(const std::string& text, Vec3& colour) {
    if (text.size() != 4 && text.size() != 7) return false;
    if (text[0] != '#') return false;
    const bool shortForm = text.size() == 4;
    for (int k = 0; k < 3; ++k) {
        int v = 0;
        if (shortForm) {
            const int d = hexDigit(text[1 + k]);
            if (d < 0) return false;
            v = d * 17;
        } else {
            const int hi = hexDigit(text[1 + 2 * k]), lo = hexDigit(text[2 + 2 * k]);
            if (hi < 0 || lo < 0) return false;
            v = hi * 16 + lo;
        }
        colour[k] = v / 255.0;
    }
    return true;
}

}  // namespace gm
