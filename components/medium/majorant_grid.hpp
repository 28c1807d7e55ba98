#pragma once
// A coarse grid of majorants over a box, walked along a ray one cell at a time: each
// cell holds a bound on σt over the cell, so delta and ratio tracking take short steps
// only where the medium is dense, and none in empty cells (Novák et al. 2018, §4.1;
// pbrt-v4's MajorantGrid). The walk is a 3-D DDA (Amanatides & Woo 1987), made
// stateless to answer IMedium::majorant(ray, tMin, tMax): from tMin it finds the cell
// that ray(tMin) lies in and the parameter where the ray leaves it, so every call
// returns the next piece — before the box (σt = 0), one cell, or past the box (σt = 0).
//
// Rounding: the box and every cell's bound are taken a little larger than exact (the
// margin below, ~1e-4 of the box), far more than the float rounding of the points
// ray(t) a caller evaluates near a cell face; a piece never ends at or before tMin (a
// ray started on a face steps on into the next cell).
//
// References: J. Amanatides & A. Woo, "A fast voxel traversal algorithm for ray
// tracing", Eurographics 1987; J. Novák, I. Georgiev, J. Hanika & W. Jarosz, "Monte
// Carlo methods for volumetric light transport simulation", Computer Graphics Forum
// 37(2), 2018; M. Pharr, W. Jakob & G. Humphreys, pbrt-v4, §11.4.3.
#include "effigi/math/bbox.hpp"
#include "effigi/render/ray.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace effigi {

class MajorantGrid {
public:
    /// One piece of a ray: up to tMax; `inside` tells whether it lies in the box, and
    /// then `bound` is its cell's bound.
    struct Piece {
        float tMax = 0.f;
        float bound = 0.f;
        bool inside = false;
    };

    MajorantGrid() = default;
    /// `res` cells per axis over `box`; boundIn(cellBox) bounds σt over a (slightly
    /// enlarged) cell.
    template <typename BoundIn>
    MajorantGrid(const BBox3f& box, int res, BoundIn&& boundIn) : m_res(std::max(1, res)) {
        const glm::dvec3 lo(box.min), hi(box.max);
        const double margin = 1e-4 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-3});
        m_lo = lo - margin;
        m_hi = hi + margin;
        m_cell = (m_hi - m_lo) / double(m_res);
        m_bounds.resize(std::size_t(m_res) * m_res * m_res);
        for (int z = 0; z < m_res; ++z)
            for (int y = 0; y < m_res; ++y)
                for (int x = 0; x < m_res; ++x) {
                    const glm::dvec3 a = m_lo + glm::dvec3(x, y, z) * m_cell - margin;
                    const glm::dvec3 b = m_lo + glm::dvec3(x + 1, y + 1, z + 1) * m_cell + margin;
                    const float v = boundIn(BBox3f(Point3f(a), Point3f(b)));
                    m_bounds[index(x, y, z)] = v;
                    m_max = std::max(m_max, v);
                }
    }

    /// The piece of `ray` from tMin (tMin < piece.tMax ≤ tMax).
    Piece piece(const Ray& ray, float tMin, float tMax) const {
        const glm::dvec3 o(ray.o), d(ray.d);
        double enter = -std::numeric_limits<double>::infinity(), exit = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0.0) {
                if (!(o[a] >= m_lo[a] && o[a] <= m_hi[a])) return {tMax, 0.f, false};
                continue;
            }
            double t0 = (m_lo[a] - o[a]) / d[a], t1 = (m_hi[a] - o[a]) / d[a];
            if (t0 > t1) std::swap(t0, t1);
            enter = std::max(enter, t0);
            exit = std::min(exit, t1);
        }
        // Missed, or the box lies wholly before tMin or after tMax.
        if (!(enter <= exit) || !(exit > double(tMin)) || !(enter < double(tMax))) return {tMax, 0.f, false};
        if (enter > double(tMin)) {
            const float e = float(enter);
            if (e > tMin) return {std::min(e, tMax), 0.f, false};
        }
        const glm::dvec3 q = o + double(tMin) * d;
        int c[3];
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor((q[a] - m_lo[a]) / m_cell[a]);
            c[a] = std::isfinite(f) ? int(std::clamp(f, 0.0, double(m_res - 1))) : 0;
        }
        // The cell's exit; where ray(tMin) sits on a face, rounding may put it in the
        // cell it is leaving: then step on into the next one.
        for (int attempt = 0; attempt < 4; ++attempt) {
            double next = exit;
            int axis = -1;
            for (int a = 0; a < 3; ++a) {
                if (d[a] == 0.0) continue;
                const double face = m_lo[a] + double(c[a] + (d[a] > 0.0 ? 1 : 0)) * m_cell[a];
                const double t = (face - o[a]) / d[a];
                if (t < next) next = t, axis = a;
            }
            const float end = float(std::min(next, double(tMax)));
            if (end > tMin) return {end, m_bounds[index(c[0], c[1], c[2])], true};
            if (axis < 0) break;
            c[axis] += d[axis] > 0.0 ? 1 : -1;
            if (c[axis] < 0 || c[axis] >= m_res) break;
        }
        // No float parameter lies between tMin and the face: the smallest step, under the
        // largest bound of all.
        return {std::min(std::nextafter(tMin, Infinity), tMax), m_max, true};
    }

    float maxBound() const { return m_max; }

private:
    std::size_t index(int x, int y, int z) const { return (std::size_t(z) * m_res + std::size_t(y)) * m_res + std::size_t(x); }

    int m_res = 1;
    glm::dvec3 m_lo{0.0}, m_hi{0.0}, m_cell{1.0};
    std::vector<float> m_bounds;
    float m_max = 0.f;
};

} // namespace effigi
