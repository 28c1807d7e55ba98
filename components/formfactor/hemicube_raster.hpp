#pragma once
// The z-buffer rasteriser of formfactor "hemicube": clip a convex polygon to one face's
// frustum, project it and draw it into an id buffer. It is watertight: polygons that
// share an edge compute the same clipped points and the same edge functions (from the
// edge's endpoints in a canonical order), and a pixel centre on a shared edge belongs to
// exactly one of them, so in a closed enclosure every pixel is drawn and none twice.
#include "effigi/math/vector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace effigi::hemicube {

constexpr std::uint32_t None = 0xffffffffu;

/// p < q lexicographically.
inline bool before(const Vector3f& p, const Vector3f& q) {
    return p.x < q.x || (p.x == q.x && (p.y < q.y || (p.y == q.y && p.z < q.z)));
}

/// One edge of a triangle in screen space as a canonical line: e(X, Y) =
/// sign · (dx (Y − ay) − dy (X − ax)) with (ax, ay) the lexicographically first endpoint.
struct Edge {
    float ax, ay, dx, dy, sign;
    bool positiveSide;  // a pixel exactly on the edge belongs to the triangle on the + side

    Edge(float px, float py, float qx, float qy) {
        bool canonical = px < qx || (px == qx && py <= qy);
        if (!canonical) std::swap(px, qx), std::swap(py, qy);
        ax = px, ay = py, dx = qx - px, dy = qy - py, sign = canonical ? 1.f : -1.f;
        positiveSide = canonical;
    }
    float rowTerm(float Y) const { return dx * (Y - ay); }
    float at(float row, float X) const { return sign * (row - dy * (X - ax)); }
};

/// Draw a triangle (screen positions px, py; 1/z in w) with `id` where it is closest.
inline void rasterTriangle(const float* px, const float* py, const float* w, int width, int height, std::uint32_t id,
                           std::uint32_t* ids, float* depth) {
    Edge eab(px[0], py[0], px[1], py[1]), ebc(px[1], py[1], px[2], py[2]), eca(px[2], py[2], px[0], py[0]);
    float area = eab.at(eab.rowTerm(py[2]), px[2]);
    if (!(std::abs(area) > 0.f)) return;
    const float orient = area > 0.f ? 1.f : -1.f, inv = 1.f / area;
    auto inside = [orient](float e, const Edge& edge) {
        float v = orient * e;
        return v > 0.f || (v == 0.f && (edge.positiveSide ? orient : -orient) > 0.f);
    };
    int x0 = std::max(0, int(std::floor(std::min({px[0], px[1], px[2]}))));
    int x1 = std::min(width - 1, int(std::ceil(std::max({px[0], px[1], px[2]}))));
    int y0 = std::max(0, int(std::floor(std::min({py[0], py[1], py[2]}))));
    int y1 = std::min(height - 1, int(std::ceil(std::max({py[0], py[1], py[2]}))));
    for (int y = y0; y <= y1; ++y) {
        float Y = float(y) + 0.5f;
        float rab = eab.rowTerm(Y), rbc = ebc.rowTerm(Y), rca = eca.rowTerm(Y);
        for (int x = x0; x <= x1; ++x) {
            float X = float(x) + 0.5f;
            float ab = eab.at(rab, X), bc = ebc.at(rbc, X), ca = eca.at(rca, X);
            if (!inside(ab, eab) || !inside(bc, ebc) || !inside(ca, eca)) continue;
            // Barycentric weights: of vertex 2 from edge 0→1, of 0 from 1→2, of 1 from 2→0.
            float d = (bc * w[0] + ca * w[1] + ab * w[2]) * inv;  // 1/z is affine on the screen
            std::size_t p = std::size_t(y) * width + x;
            if (d > depth[p]) {
                depth[p] = d;
                ids[p] = id;
            }
        }
    }
}

/// Clip a convex polygon (face coordinates: x, y on the face, z along its axis) to
/// z ≥ zNear, |x| ≤ 1.5 z, y ≤ 1.5 z and y ≥ −1.5 z (top face) or y ≥ 0 (side faces);
/// the guard band keeps projected coordinates small enough for float edge functions.
/// Then project (x/z, y/z) onto a width × height pixel grid whose pixels are 2/width
/// wide and draw it as a fan.
inline void rasterPolygon(const Vector3f* in, int n, float zNear, bool side, int width, int height, std::uint32_t id,
                          std::uint32_t* ids, float* depth) {
    constexpr int Max = 16;
    constexpr float G = 1.5f;
    auto plane = [&](int which, const Vector3f& p) {
        switch (which) {
        case 0: return p.z - zNear;
        case 1: return G * p.z - p.x;
        case 2: return G * p.z + p.x;
        case 3: return G * p.z - p.y;
        default: return side ? p.y : G * p.z + p.y;
        }
    };
    // Trivial rejection: every corner outside one plane.
    for (int which = 0; which < 5; ++which) {
        bool allOut = true;
        for (int k = 0; k < n && allOut; ++k) allOut = plane(which, in[k]) < 0.f;
        if (allOut) return;
    }
    Vector3f c[Max], tmp[Max];
    int m = n;
    std::copy(in, in + n, c);
    for (int which = 0; which < 5 && m >= 3; ++which) {
        int out = 0;
        for (int k = 0; k < m; ++k) {
            const Vector3f &a = c[k], &b = c[(k + 1) % m];
            float da = plane(which, a), db = plane(which, b);
            if (da >= 0.f && out < Max) tmp[out++] = a;
            if ((da >= 0.f) != (db >= 0.f) && out < Max) {
                // From the endpoints in a canonical order: the polygon on the other side
                // of a shared edge gets the very same point.
                bool swap = before(b, a);
                const Vector3f &lo = swap ? b : a, &hi = swap ? a : b;
                float dlo = swap ? db : da, dhi = swap ? da : db;
                tmp[out++] = lo + (dlo / (dlo - dhi)) * (hi - lo);
            }
        }
        m = out;
        std::copy(tmp, tmp + m, c);
    }
    if (m < 3) return;
    const float scale = 0.5f * float(width), oy = side ? 0.f : 1.f;
    float px[Max], py[Max], w[Max];
    for (int k = 0; k < m; ++k) {
        w[k] = 1.f / c[k].z;
        px[k] = (c[k].x * w[k] + 1.f) * scale;
        py[k] = (c[k].y * w[k] + oy) * scale;
    }
    for (int k = 1; k + 1 < m; ++k) {
        float tx[3] = {px[0], px[k], px[k + 1]}, ty[3] = {py[0], py[k], py[k + 1]}, tw[3] = {w[0], w[k], w[k + 1]};
        rasterTriangle(tx, ty, tw, width, height, id, ids, depth);
    }
}

} // namespace effigi::hemicube
