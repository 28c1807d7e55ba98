// Grids and polygon triangulation for the RIB translator (tessellate.hpp).
#include "tessellate.hpp"

#include "effigi/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace effigi::rib {

TriangleMesh gridMesh(int nu, int nv, const SurfaceFn& f) {
    TriangleMesh m;
    const std::size_t verts = std::size_t(nu + 1) * std::size_t(nv + 1);
    m.positions.reserve(verts);
    m.normals.reserve(verts);
    m.uvs.reserve(verts);
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const double u = double(i) / nu, v = double(j) / nv;
            Vector3d p, n;
            f(u, v, p, n);
            // float holds up to 3.4e38; RIB numbers are at most 1e38 (lexer.hpp).
            if (!(std::abs(p.x) <= 1e38 && std::abs(p.y) <= 1e38 && std::abs(p.z) <= 1e38))
                fail("a vertex of the surface is out of range (beyond ±1e38)");
            m.positions.emplace_back(p);
            double len = glm::length(n);
            m.normals.push_back(len > 0.0 && std::isfinite(len) ? Normal3f(n / len) : Normal3f(0.f));
            m.uvs.emplace_back(float(u), float(v));
        }
    auto at = [&](int i, int j) { return std::uint32_t(j * (nu + 1) + i); };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
        }
    return m;
}

namespace {

void fan(const std::vector<std::uint32_t>& loop, std::vector<std::uint32_t>& out) {
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) out.insert(out.end(), {loop[0], loop[k], loop[k + 1]});
}

double cross2(const Vector2f& a, const Vector2f& b, const Vector2f& c) {
    return double(b.x - a.x) * double(c.y - a.y) - double(b.y - a.y) * double(c.x - a.x);
}

bool inTriangle(const Vector2f& p, const Vector2f& a, const Vector2f& b, const Vector2f& c) {
    return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

} // namespace

void triangulate(const std::vector<Point3f>& points, const std::vector<std::uint32_t>& loop, bool convex,
                 std::vector<std::uint32_t>& out) {
    const std::size_t n = loop.size();
    if (convex || n <= 3 || n > 256) return fan(loop, out);
    // Newell's normal; the polygon is projected onto the plane of its two smaller axes,
    // mirrored if need be so that it winds counter-clockwise there.
    Vector3d normal(0.0);
    for (std::size_t i = 0; i < n; ++i) {
        Vector3d a(points[loop[i]]), b(points[loop[(i + 1) % n]]);
        normal += Vector3d((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    Vector3d an = glm::abs(normal);
    int drop = an.x >= an.y && an.x >= an.z ? 0 : an.y >= an.z ? 1 : 2;
    if (!(an[drop] > 0.0)) return fan(loop, out);  // degenerate: no plane
    const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
    const float flip = normal[drop] < 0.0 ? -1.f : 1.f;
    std::vector<Vector2f> p2(n);
    for (std::size_t i = 0; i < n; ++i) p2[i] = Vector2f(points[loop[i]][ax], flip * points[loop[i]][ay]);

    std::vector<std::size_t> rest(n);
    for (std::size_t i = 0; i < n; ++i) rest[i] = i;
    while (rest.size() > 3) {
        const std::size_t m = rest.size();
        bool clipped = false;
        for (std::size_t k = 0; k < m && !clipped; ++k) {
            std::size_t a = rest[(k + m - 1) % m], b = rest[k], c = rest[(k + 1) % m];
            if (!(cross2(p2[a], p2[b], p2[c]) > 0.0)) continue;  // reflex or flat: not an ear
            bool empty = true;
            for (std::size_t q : rest)
                if (q != a && q != b && q != c && p2[q] != p2[a] && p2[q] != p2[b] && p2[q] != p2[c] &&
                    inTriangle(p2[q], p2[a], p2[b], p2[c])) {
                    empty = false;
                    break;
                }
            if (!empty) continue;
            out.insert(out.end(), {loop[a], loop[b], loop[c]});
            rest.erase(rest.begin() + std::ptrdiff_t(k));
            clipped = true;
        }
        if (!clipped) {  // self-intersecting or degenerate: a fan of what is left
            std::vector<std::uint32_t> left;
            for (std::size_t q : rest) left.push_back(loop[q]);
            return fan(left, out);
        }
    }
    out.insert(out.end(), {loop[rest[0]], loop[rest[1]], loop[rest[2]]});
}

void orientTriangles(TriangleMesh& m, bool mirrored) {
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        std::uint32_t* idx = &m.indices[t];
        bool turn = mirrored;
        if (!m.normals.empty()) {
            Vector3f ng = cross(m.positions[idx[1]] - m.positions[idx[0]], m.positions[idx[2]] - m.positions[idx[0]]);
            Vector3f ns = m.normals[idx[0]] + m.normals[idx[1]] + m.normals[idx[2]];
            if (dot(ng, ns) < 0.f) turn = !turn;
        }
        if (turn) std::swap(idx[1], idx[2]);
    }
}

} // namespace effigi::rib
