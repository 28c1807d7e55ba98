#pragma once
// The data layout of store "hashgrid" (hashgrid.cpp has the design and the references):
// choosing the cell size, sorting events into cells by hash, and visiting the events of a
// block, a shell or a box of cells with exact (conservatively widened) cell bounds.
#include "event_store.hpp"

#include "effigi/math/rng.hpp"  // mixBits

#include <array>
#include <bit>

namespace effigi::store {

/// Integer cell of a point, clamped into the grid (finite = the point was finite).
struct GridPoint {
    std::array<std::int64_t, 3> i{};
    bool finite = false;
};

/// A box of cells [lo, hi] (inclusive), inside the grid.
struct CellRange {
    std::array<std::int64_t, 3> lo{}, hi{};
    double cells() const { return double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1); }
};

class HashGridLayout {
public:
    static constexpr std::int64_t MaxDim = std::int64_t(1) << 21;  ///< cells per axis (exact 63-bit keys)
    static constexpr double TargetOccupancy = 4.0;                ///< events per cell, radiusHint = 0

    void build(std::span<const Point3f> points, float radiusHint, float factor);

    /// Non-empty cells.
    std::size_t cellCount() const { return m_cellCount; }
    std::size_t memoryBytes() const { return m_nodes.capacity() * sizeof(Node) + m_table.capacity() * sizeof(Cell); }

    GridPoint cellOf(const Point3f& p) const {
        GridPoint g;
        g.finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        for (int a = 0; a < 3 && g.finite; ++a)
            g.i[a] = std::int64_t(std::clamp(std::floor((double(p[a]) - m_origin[a]) * m_inv), 0.0, double(m_dims[a] - 1)));
        return g;
    }

    /// The cells a ball (q, r) may reach, widened for rounding; false if it misses the grid.
    bool ballRange(const Point3f& q, double r, CellRange& out) const {
        const double pad = r * (1.0 + RelSlop) + absSlop(q);
        for (int a = 0; a < 3; ++a) {
            double lo = std::floor((double(q[a]) - pad - m_origin[a]) * m_inv);
            double hi = std::floor((double(q[a]) + pad - m_origin[a]) * m_inv);
            if (hi < 0.0 || lo > double(m_dims[a] - 1)) return false;
            out.lo[a] = std::int64_t(std::max(lo, 0.0));
            out.hi[a] = std::int64_t(std::min(hi, double(m_dims[a] - 1)));
        }
        return true;
    }

    /// Cells of the block [c − s, c + s]³ inside the grid.
    double blockCells(const GridPoint& c, std::int64_t s) const { return block(c, s).cells(); }
    bool blockCoversGrid(const GridPoint& c, std::int64_t s) const {
        for (int a = 0; a < 3; ++a)
            if (c.i[a] - s > 0 || c.i[a] + s < m_dims[a] - 1) return false;
        return true;
    }
    /// A lower bound of the distance from q to any event outside the block (∞ on sides
    /// where the block reaches the grid's end), shrunk for rounding.
    double gapOutside(const Point3f& q, const GridPoint& c, std::int64_t s) const {
        double gap = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            if (c.i[a] - s > 0) gap = std::min(gap, double(q[a]) - face(a, c.i[a] - s));
            if (c.i[a] + s < m_dims[a] - 1) gap = std::min(gap, face(a, c.i[a] + s + 1) - double(q[a]));
        }
        return gap * (1.0 - RelSlop) - absSlop(q);
    }

    /// visit(d², index) for the events of every cell of `range` whose lower bound of d²
    /// is ≤ bound().
    template <typename Visit, typename Bound>
    void visitRange(const Point3f& q, const CellRange& r, Visit&& visit, Bound&& bound) const {
        const double slop = absSlop(q);
        for (std::int64_t z = r.lo[2]; z <= r.hi[2]; ++z) {
            const double gz = axisGap(q, 2, z, slop);
            for (std::int64_t y = r.lo[1]; y <= r.hi[1]; ++y) {
                const double gyz = gz + axisGap(q, 1, y, slop);
                for (std::int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
                    if (gyz + axisGap(q, 0, x, slop) <= double(bound())) visitCell(q, {x, y, z}, visit);
            }
        }
    }

    /// The cells at Chebyshev distance exactly s from c (s = 0: c itself), as visitRange.
    template <typename Visit, typename Bound>
    void visitShell(const Point3f& q, const GridPoint& c, std::int64_t s, Visit&& visit, Bound&& bound) const {
        const CellRange b = block(c, s);
        CellRange face = b;
        for (int a = 0; a < 3; ++a) {
            // The two faces of the block normal to axis a, without the cells of faces
            // normal to earlier axes (already visited).
            for (int end = 0; end < (s == 0 ? 1 : 2); ++end) {
                const std::int64_t side = end == 0 ? c.i[a] - s : c.i[a] + s;
                if (side < b.lo[a] || side > b.hi[a]) continue;
                face.lo[a] = face.hi[a] = side;
                visitRange(q, face, visit, bound);
            }
            // Faces normal to later axes exclude the layers at c ± s along axis a.
            face.lo[a] = std::max(b.lo[a], c.i[a] - s + 1);
            face.hi[a] = std::min(b.hi[a], c.i[a] + s - 1);
            if (face.lo[a] > face.hi[a]) return;
        }
    }

    /// visit(d², index) for every event (storage order).
    template <typename Visit> void visitAll(const Point3f& q, Visit&& visit) const {
        for (const Node& n : m_nodes) visit(eventDistance2(q, n.p), n.index);
    }

private:
    struct Node {
        Point3f p;
        std::uint32_t index;
    };
    static constexpr double RelSlop = 1e-5;  // ≫ the relative error of a float d² (~4·2⁻²⁴)

    /// Absolute rounding allowance: d² underflow (below 1e-36) and double cell arithmetic.
    double absSlop(const Point3f& q) const {
        return 1e-18 + 1e-12 * (m_scale + std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}));
    }
    double face(int a, std::int64_t i) const { return m_origin[a] + double(i) * m_cell; }
    /// Lower bound of (q[a] − x[a])² over the events of cell layer i on axis a.
    double axisGap(const Point3f& q, int a, std::int64_t i, double slop) const {
        const double g = std::max({face(a, i) - double(q[a]), double(q[a]) - face(a, i + 1), 0.0});
        const double lower = std::max(g * (1.0 - RelSlop) - slop, 0.0);
        return lower * lower;
    }
    CellRange block(const GridPoint& c, std::int64_t s) const {
        CellRange b;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::max<std::int64_t>(c.i[a] - s, 0);
            b.hi[a] = std::min<std::int64_t>(c.i[a] + s, m_dims[a] - 1);
        }
        return b;
    }
    static std::uint64_t key(const std::array<std::int64_t, 3>& i) {
        return std::uint64_t(i[0]) | std::uint64_t(i[1]) << 21 | std::uint64_t(i[2]) << 42;
    }

    /// Open addressing with linear probing (the table is at most half full): one cache
    /// line per cell looked up, then the cell's events, contiguous.
    template <typename Visit> void visitCell(const Point3f& q, const std::array<std::int64_t, 3>& i, Visit& visit) const {
        const std::uint64_t k = key(i);
        for (std::uint64_t s = mixBits(k) & m_tableMask;; s = (s + 1) & m_tableMask) {
            const Cell& c = m_table[s];
            if (c.key == k) {
                for (std::uint32_t e = c.begin; e < c.end; ++e) visit(eventDistance2(q, m_nodes[e].p), m_nodes[e].index);
                return;
            }
            if (c.key == EmptyKey) return;
        }
    }

    double dataCellSize(const std::array<double, 3>& extent, std::size_t n) const;
    void clampCellSize(std::size_t n, const std::array<double, 3>& extent);
    void sortIntoCells(std::span<const Point3f> points);

    std::array<double, 3> m_origin{};
    std::array<std::int64_t, 3> m_dims{1, 1, 1};
    double m_cell = 1.0, m_inv = 1.0, m_scale = 0.0;
    struct Cell {
        std::uint64_t key;          ///< EmptyKey: a free slot
        std::uint32_t begin, end;   ///< its events: m_nodes[begin, end)
    };
    static constexpr std::uint64_t EmptyKey = ~std::uint64_t(0);  // keys use 63 bits

    std::vector<Node> m_nodes;   // events, cell by cell
    std::vector<Cell> m_table;   // the non-empty cells, hashed by key
    std::uint64_t m_tableMask = 0;
    std::size_t m_cellCount = 0;
};

} // namespace effigi::store
