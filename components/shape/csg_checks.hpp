#pragma once
// Whether a csg part bounds a solid (components/shape/csg.cpp), and which way its normals
// point: a triangle mesh by its edges (every edge of the welded mesh shared by triangles
// that traverse it in opposite directions, in equal numbers), an analytic shape by its
// area samples and Gauss's theorem. Both give the part's signed volume, whose sign says
// whether the normals point out of the solid (flip_normals, inward winding) or into it.
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/sample_sequences.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

namespace effigi::csg {

/// Why the mesh is not the closed, consistently oriented surface of a solid (empty when
/// it is); `volume` gets its signed volume, > 0 when wound outward.
inline std::string meshSolidProblem(const TriangleMesh& m, double& volume) {
    // Weld by position: meshes split vertices at uv and normal seams (cube's 24 corners).
    std::vector<std::pair<Point3f, std::uint32_t>> order(m.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = {m.positions[i], i};
    auto less = [](const Point3f& a, const Point3f& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) { return less(a.first, b.first); });
    std::vector<std::uint32_t> weld(m.positions.size());
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (i > 0 && order[i].first != order[i - 1].first) ++id;
        weld[order[i].second] = id;
    }
    struct Edge {
        std::uint32_t a, b;
        int sign;
    };
    std::vector<Edge> edges;
    volume = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const std::uint32_t* idx = &m.indices[3 * t];
        Vector3d p0(m.positions[idx[0]]), p1(m.positions[idx[1]]), p2(m.positions[idx[2]]);
        volume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
        std::uint32_t w[3] = {weld[idx[0]], weld[idx[1]], weld[idx[2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;  // degenerate: no edges of its own
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = w[k], b = w[(k + 1) % 3];
            edges.push_back(a < b ? Edge{a, b, 1} : Edge{b, a, -1});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
    std::size_t open = 0, misoriented = 0;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        int sum = 0;
        for (; j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b; ++j) sum += edges[j].sign;
        if ((j - i) % 2) ++open;
        else if (sum != 0) ++misoriented;
        i = j;
    }
    if (open) return fmt::format("its surface is not closed ({} edges border an odd number of triangles)", open);
    if (misoriented) return fmt::format("its triangles are not consistently oriented ({} edges)", misoriented);
    if (!(volume != 0.0)) return "it encloses no volume";
    return {};
}

/// The same for an analytic shape. By Gauss's theorem ∮ n (p − c)ᵀ dA = V I for a closed
/// surface enclosing volume V (any c); an open one (a cylinder without caps, a disk)
/// breaks it. Estimated from 4096 area samples at the points of a Hammersley set, which
/// for the smooth closed shapes is good to far better than the 10 % asked.
inline std::string sampledSolidProblem(const IShape& s, double& volume) {
    constexpr std::uint32_t N = 4096;
    const Vector3d c(s.bbox().center());
    glm::dmat3 m(0.0);
    for (std::uint32_t i = 0; i < N; ++i) {
        PositionSample ps = s.samplePosition({(float(i) + 0.5f) / float(N), fixedToFloat(vanDerCorput(i))});
        if (!(ps.pdf > 0.f) || !isFinite(ps.p) || !isFinite(ps.n)) return "it gives no area samples to check it is closed";
        m += glm::outerProduct(Vector3d(ps.n), Vector3d(ps.p) - c) / (double(ps.pdf) * double(N));
    }
    volume = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
    double deviation = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) deviation = std::max(deviation, std::abs(m[i][j] - (i == j ? volume : 0.0)));
    if (!(std::abs(volume) > 0.0) || !(deviation <= 0.1 * std::abs(volume)))
        return "its surface is not closed (Gauss's theorem fails on its area samples)";
    return {};
}

} // namespace effigi::csg
