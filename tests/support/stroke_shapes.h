// Test support: stroked flat shapes of every kind, for the writers' and consumers' tests.
#pragma once

#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gmtest {

// Appends to a centreline (which holds its start) a straight segment to b, its handles at the
// thirds.
inline void lineTo(std::vector<gm::Vec2>& path, gm::Vec2 b) {
    const gm::Vec2 a = path.back();
    path.insert(path.end(), {a + (1.0 / 3) * (b - a), a + (2.0 / 3) * (b - a), b});
}

inline gm::FlatShape stroke(gm::Vec3 col, double width, std::vector<std::vector<gm::Vec2>> lines,
                            double alpha = 1) {
    gm::FlatShape s;
    s.col = col;
    s.alpha = alpha;
    s.strokeWidth = width;
    s.subpaths = std::move(lines);
    return s;
}

// On a 200 × 140 canvas, all at layer 0: a filled square, then strokes over it and beside it:
// an open zigzag of lines; an open line-and-curves path; a closed circle of four cubics; a
// translucent shape of two centrelines (a closed triangle and an open line); a thin straight
// line.
inline std::vector<gm::FlatShape> strokeTestShapes() {
    using gm::Vec2;
    std::vector<gm::FlatShape> shapes;
    gm::FlatShape square;
    square.col = {0.95, 0.85, 0.3};
    square.subpaths = {gm::polygonAsCubics({{100, 20}, {170, 20}, {170, 90}, {100, 90}})};
    shapes.push_back(square);

    std::vector<Vec2> zigzag{{15, 20}};
    for (Vec2 p : {Vec2{45, 50}, Vec2{75, 20}, Vec2{105, 50}}) lineTo(zigzag, p);
    shapes.push_back(stroke({0.7, 0.1, 0.1}, 3, {zigzag}));

    std::vector<Vec2> wave{{15, 110}};
    lineTo(wave, {35, 100});
    wave.insert(wave.end(), {{50, 75}, {75, 140}, {90, 110}, {105, 80}, {130, 135}, {150, 100}});
    shapes.push_back(stroke({0.1, 0.3, 0.8}, 5.5, {wave}));

    constexpr double kappa = 0.5522847498307936;
    const Vec2 c{140, 55};
    const double r = 25;
    const Vec2 dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    std::vector<Vec2> circle;
    for (int k = 0; k < 4; ++k) {
        const Vec2 a = dirs[k], b = dirs[(k + 1) % 4];
        circle.insert(circle.end(),
                      {c + r * a, c + r * a + (kappa * r) * b, c + r * b + (kappa * r) * a});
    }
    circle.push_back(circle.front());
    shapes.push_back(stroke({0.1, 0.6, 0.2}, 2.25, {circle}));

    std::vector<Vec2> triangle{{30, 70}};
    for (Vec2 p : {Vec2{70, 75}, Vec2{45, 95}, Vec2{30, 70}}) lineTo(triangle, p);
    std::vector<Vec2> dash{{160, 115}};
    lineTo(dash, {185, 130});
    shapes.push_back(stroke({0.5, 0.2, 0.6}, 4, {triangle, dash}, 0.6));

    std::vector<Vec2> thin{{10, 130}};
    lineTo(thin, {190, 124});
    shapes.push_back(stroke({0.2, 0.2, 0.2}, 1.2, {thin}));
    return shapes;
}

inline gm::Document strokeTestDocument() {
    gm::Document d;
    d.width = 200;
    d.height = 140;
    d.shapes = strokeTestShapes();
    return d;
}

}  // namespace gmtest
