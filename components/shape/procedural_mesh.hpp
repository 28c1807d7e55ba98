#pragma once
// What the procedural mesh shapes (revolution, sweep, and subdiv's inline cage) share:
// number lists written in one string parameter ("a b, c d, ..."), uniform Catmull–Rom
// splines through points with their exact derivative, and a grid of quads between rows
// and columns of generated vertices, wound so that (column step) × (row step) faces out.
// Reference: E. Catmull, R. Rom, "A class of local interpolating splines", Computer Aided
// Geometric Design, 1974.
#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/core/properties.hpp"
#include "effigi/render/mesh.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace effigi::procedural {

/// The tuples of a list parameter: numbers separated by blanks, tuples by commas. Each
/// tuple has `arity` numbers (0: any number, at least one); at least minCount tuples.
/// Errors name the parameter and its place in the scene.
inline std::vector<std::vector<double>> parseTuples(const Properties& p, const std::string& name, std::size_t arity,
                                                    std::size_t minCount) {
    const std::string& text = p.getString(name);
    auto bad = [&](const std::string& why) -> void { failAt(p.whereOf(name), "{}: parameter '{}': {}", p.describe(), name, why); };
    std::vector<std::vector<double>> tuples;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        std::string item = text.substr(start, comma - start);
        std::vector<double> t;
        const char* cur = item.c_str();
        for (;;) {
            char* end;
            double v = std::strtod(cur, &end);
            if (end == cur) break;
            if (!std::isfinite(v)) bad(fmt::format("tuple {} holds a non-finite number", tuples.size() + 1));
            t.push_back(v);
            cur = end;
        }
        if (std::string(cur).find_first_not_of(" \t\r\n") != std::string::npos)
            bad(fmt::format("tuple {}: '{}' is not a number", tuples.size() + 1, excerpt(cur)));
        if (t.empty() && !(comma == text.size() && !tuples.empty()))  // a trailing comma is fine
            bad(fmt::format("tuple {} is empty", tuples.size() + 1));
        if (!t.empty()) {
            if (arity && t.size() != arity)
                bad(fmt::format("tuple {} has {} numbers, expected {}", tuples.size() + 1, t.size(), arity));
            tuples.push_back(std::move(t));
        }
        start = comma + 1;
    }
    if (tuples.size() < minCount) bad(fmt::format("needs at least {} tuples, got {}", minCount, tuples.size()));
    return tuples;
}

/// A uniform Catmull–Rom spline through points, open: the phantom points beyond the ends
/// continue the parabola through the last three points (Bessel's end condition; a line
/// with two points), so the end tangents are second-order accurate, two points give a
/// straight line at constant speed, and points spaced evenly on a line are reproduced
/// exactly. Segment k runs from point k to point k + 1 as t goes from 0 to 1.
template <class V> struct CatmullRom {
    std::vector<V> pts;

    std::size_t segments() const { return pts.size() - 1; }
    V at(std::ptrdiff_t i) const {
        const std::size_t n = pts.size();
        if (i >= 0 && std::size_t(i) < n) return pts[std::size_t(i)];
        // p0, p1, p2: the end point and the next two inwards.
        const V& p0 = i < 0 ? pts[0] : pts[n - 1];
        const V& p1 = i < 0 ? pts[1] : pts[n - 2];
        if (n == 2) return 2.0 * p0 - p1;
        const V& p2 = i < 0 ? pts[2] : pts[n - 3];
        return 3.0 * p0 - 3.0 * p1 + p2;
    }
    /// Position and derivative d/dt on segment k at t in [0, 1].
    void eval(std::size_t k, double t, V& p, V& dp) const {
        const auto i = std::ptrdiff_t(k);
        V p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
        double t2 = t * t, t3 = t2 * t;
        p = 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                   (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3);
        dp = 0.5 * ((p2 - p0) + 2.0 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t +
                    3.0 * (3.0 * p1 - p0 - 3.0 * p2 + p3) * t2);
    }
};

/// One generated vertex.
struct GridVertex {
    Point3f p;
    Normal3f n;
    Point2f uv;
};

/// Appends rows × cols vertices vertex(i, j) and the quads (two triangles each) between
/// rows i, i+1 where rowLinked(i) and columns j, j+1 where colLinked(j): a strip that is
/// not linked leaves a sharp edge (its vertices are repeated with other normals). A
/// triangle with two corners at the same position (on a rotation axis) is left out.
template <class VertexFn, class RowFn, class ColFn>
void appendGrid(TriangleMesh& m, std::size_t rows, std::size_t cols, VertexFn vertex, RowFn rowLinked, ColFn colLinked) {
    const auto base = std::uint32_t(m.positions.size());
    for (std::size_t i = 0; i < rows; ++i)
        for (std::size_t j = 0; j < cols; ++j) {
            GridVertex v = vertex(i, j);
            m.positions.push_back(v.p);
            m.normals.push_back(v.n);
            m.uvs.push_back(v.uv);
        }
    auto id = [&](std::size_t i, std::size_t j) { return base + std::uint32_t(i * cols + j); };
    auto triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const std::vector<Point3f>& P = m.positions;
        if (P[a] == P[b] || P[b] == P[c] || P[c] == P[a]) return;
        m.indices.insert(m.indices.end(), {a, b, c});
    };
    for (std::size_t i = 0; i + 1 < rows; ++i) {
        if (!rowLinked(i)) continue;
        for (std::size_t j = 0; j + 1 < cols; ++j) {
            if (!colLinked(j)) continue;
            triangle(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            triangle(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        }
    }
}

} // namespace effigi::procedural
