// store "hashgrid" — a uniform grid of cubic cells over the events' bounding box, hashed
// by integer cell (Teschner et al. 2003; the grid of Hachisuka & Jensen's SPPM, 2009).
//
// Build: cell size c = cell_factor · radiusHint, or, for radiusHint = 0, c chosen from the
// data so that a non-empty cell holds about 4 events (from the volume of the non-flat
// axes, corrected by the occupancy it gives); c is raised where needed so the dense grid
// has at most 64 n cells (the query cost stays bounded) and ≤ 2²¹ cells per axis (the key
// ix | iy·2²¹ | iz·2⁴² is exact). Events are counting-sorted by hash(key) mod 2^⌈log₂ n⌉,
// then by key within a bucket, so each cell's events are contiguous; the non-empty cells
// (key, first, end) go into an open-addressing table at most half full, so a lookup
// costs about one cache line. Memory O(n): 16 bytes per event, 32–64 per non-empty
// cell, plus the positions in insertion order.
//
// radius(q, r): the cells overlapping the ball's bounding box, or — when those are more
// than the non-empty cells (r ≫ c) — every event: exact either way, cost O(min(cells, n)).
// knn(q, k, r): shells of cells at Chebyshev distance s = 0, 1, 2, … around q's cell, the
// k best in a bounded max-heap (KnnHeap); it stops when the gap from q to the outside of
// the visited block, squared, exceeds the heap's bound (so no event outside can win,
// ties included), or falls back to scanning every event when the block grows larger than
// the non-empty cells. The block and the cell ranges are widened by 1e-5 relative, plus
// 1e-18 + 1e-12 × the coordinates' magnitude, so that the float rounding of
// eventDistance2 and of the cell arithmetic can never hide an answer (event_store.hpp).
//
// Parameters:
//   cell_factor  float (default 1, 1/64..16)  cell size relative to radiusHint (or to the
//                                              size chosen from the data)
//
// Reference: M. Teschner, B. Heidelberger, M. Müller, D. Pomeranets, M. Gross, "Optimized
// Spatial Hashing for Collision Detection of Deformable Objects", VMV 2003; T. Hachisuka,
// H. W. Jensen, "Stochastic Progressive Photon Mapping", SIGGRAPH Asia 2009, §4.
#include "event_store.hpp"

#include "hash_grid_layout.hpp"

namespace effigi {
namespace {

class HashGridStore final : public store::EventStoreBase {
public:
    static Schema schema() {
        Schema s("store", "hashgrid",
                 "Uniform grid hashed by integer cell, events stored cell-contiguously; exact radius queries over "
                 "the cells a ball overlaps and k-nearest-neighbour queries by shells of cells.");
        s.cite("M. Teschner et al., Optimized Spatial Hashing for Collision Detection of Deformable Objects, VMV "
               "2003; T. Hachisuka, H. W. Jensen, Stochastic Progressive Photon Mapping, 2009");
        s.real("cell_factor", 1.0, "Cell size relative to build()'s radius hint (or to the size chosen from the data)")
            .range(1.0 / 64.0, 16.0);
        s.addConformance({"default", {}});
        return s;
    }

    explicit HashGridStore(const Properties& p) : EventStoreBase(p), m_factor(p.getFloat("cell_factor")) {}

    void clear() override {
        EventStoreBase::clear();
        m_grid = {};
    }

    void build(float radiusHint) override {
        m_grid.build(m_points, std::isfinite(radiusHint) && radiusHint > 0.f ? radiusHint : 0.f, m_factor);
        markBuilt();
    }

    std::size_t knn(const Point3f& p, std::size_t k, float maxRadius, EventNeighbour* out) const override {
        if (k == 0 || !searchable()) return 0;
        store::KnnHeap heap(out, k, maxRadius);
        auto visit = [&](float d2, std::uint32_t i) { heap.push(d2, i); };
        auto bound = [&] { return heap.bound(); };
        const store::GridPoint c = m_grid.cellOf(p);
        for (std::int64_t s = 0; c.finite; ++s) {
            // Shell s completes the block [c − s, c + s]³; every event outside it is at
            // least gapOutside away, so once that exceeds the bound none can enter.
            if (m_grid.blockCells(c, s) > double(m_grid.cellCount())) break;  // r ≫ cells: scan instead
            m_grid.visitShell(p, c, s, visit, bound);
            if (m_grid.blockCoversGrid(c, s)) return heap.finish();
            const double gap = m_grid.gapOutside(p, c, s);
            if (gap > 0.0 && gap * gap > double(heap.bound())) return heap.finish();
        }
        heap.n = 0;  // start again: the scan of every event must not see one twice
        m_grid.visitAll(p, visit);
        return heap.finish();
    }

    void radius(const Point3f& p, float r, std::vector<EventNeighbour>& out) const override {
        out.clear();
        if (!searchable()) return;
        const float r2 = r * r;
        auto visit = [&](float d2, std::uint32_t i) { if (d2 <= r2) out.push_back({i, d2}); };
        store::CellRange range;
        // r² overflowing to ∞ (or a non-finite query point) puts every event at d² = ∞
        // within reach: no cell bound applies.
        if (!std::isfinite(r2) || !m_grid.cellOf(p).finite)
            m_grid.visitAll(p, visit);
        else if (m_grid.ballRange(p, std::sqrt(double(r2)), range)) {
            if (range.cells() <= double(m_grid.cellCount()))
                m_grid.visitRange(p, range, visit, [r2] { return r2; });
            else
                m_grid.visitAll(p, visit);  // r ≫ cell: fewer events than cells to look up
        }
        std::sort(out.begin(), out.end());
    }

    std::size_t memoryBytes() const override { return sizeof(*this) + pointBytes() + m_grid.memoryBytes(); }

private:
    float m_factor;
    store::HashGridLayout m_grid;
};

} // namespace

// ---- the layout's build (hash_grid_layout.hpp) ----------------------------------------

namespace store {

void HashGridLayout::build(std::span<const Point3f> points, float radiusHint, float factor) {
    const std::size_t n = points.size();
    m_nodes.clear();
    m_table.assign(1, {EmptyKey, 0, 0});
    m_tableMask = 0;
    m_cellCount = 0;
    m_dims = {1, 1, 1};
    if (n == 0) return;
    Point3f lo = points[0], hi = lo;
    for (const Point3f& p : points) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    std::array<double, 3> extent;
    for (int a = 0; a < 3; ++a) {
        m_origin[a] = lo[a];
        extent[a] = double(hi[a]) - double(lo[a]);
    }
    m_scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    double base = radiusHint;
    if (radiusHint == 0.f) {
        // From the data: occupancy ∝ c^d for d-dimensional data; the first guess assumes
        // the non-flat axes are filled, later ones correct it by the measured exponent.
        base = dataCellSize(extent, n);
        double prevCell = 0.0, prevOcc = 0.0;
        for (int it = 0; it < 4; ++it) {
            m_cell = base;
            clampCellSize(n, extent);
            sortIntoCells(points);
            const double occ = double(n) / double(cellCount());
            if (occ <= 4.0 * TargetOccupancy || (prevCell > 0.0 && m_cell >= prevCell)) break;
            double d = prevOcc > 0.0 ? std::log(prevOcc / occ) / std::log(prevCell / m_cell) : 3.0;
            d = d >= 1.0 ? std::min(d, 3.0) : 3.0;
            prevCell = m_cell;
            prevOcc = occ;
            base = m_cell * std::pow(TargetOccupancy / occ, 1.0 / d);
        }
        if (factor == 1.f) return;
    }
    m_cell = double(factor) * base;
    clampCellSize(n, extent);
    sortIntoCells(points);
}

double HashGridLayout::dataCellSize(const std::array<double, 3>& extent, std::size_t n) const {
    const double maxExtent = std::max({extent[0], extent[1], extent[2]});
    if (!(maxExtent > 0.0)) return 1.0;  // all events at one point: any cell will do
    double volume = 1.0;
    int dims = 0;
    for (double e : extent)
        if (e > 1e-6 * maxExtent) {
            volume *= e;
            ++dims;
        }
    return std::pow(volume * TargetOccupancy / double(n), 1.0 / dims);
}

void HashGridLayout::clampCellSize(std::size_t n, const std::array<double, 3>& extent) {
    // Not so small that the cell arithmetic loses its meaning, the key its exactness or
    // the dense grid O(n) size (which bounds the cells a query may look up).
    m_cell = std::max(m_cell, 1e-30 * std::max(1.0, m_scale));
    if (!std::isfinite(m_cell)) m_cell = 1.0 + 2.0 * m_scale;
    for (int it = 0; it < 4000; ++it) {
        double d[3], cells = 1.0;
        for (int a = 0; a < 3; ++a) cells *= d[a] = std::floor(extent[a] / m_cell) + 1.0;
        if (std::max({d[0], d[1], d[2]}) < double(MaxDim) && cells <= 64.0 * double(n)) {
            for (int a = 0; a < 3; ++a) m_dims[a] = std::int64_t(d[a]);
            break;
        }
        m_cell *= 1.25;
    }
    m_inv = 1.0 / m_cell;
}

void HashGridLayout::sortIntoCells(std::span<const Point3f> points) {
    // Group events by cell: a counting sort by bucket = hash(key) mod 2^⌈log₂ n⌉, then by
    // (key, index) within a bucket (rarely needed: a bucket mostly holds one cell).
    const std::size_t n = points.size(), buckets = std::bit_ceil(n);
    std::vector<std::uint64_t> keys(n);
    std::vector<std::uint32_t> start(buckets + 1, 0), order(n);
    for (std::size_t i = 0; i < n; ++i) {
        keys[i] = key(cellOf(points[i]).i);
        ++start[(mixBits(keys[i]) & (buckets - 1)) + 1];
    }
    for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    for (std::size_t i = 0; i < n; ++i) order[start[mixBits(keys[i]) & (buckets - 1)]++] = std::uint32_t(i);
    // start[b] is now the end of bucket b.
    std::vector<Cell> cells;
    m_nodes.resize(n);
    for (std::size_t b = 0, first = 0; b < buckets; first = start[b++]) {
        const auto lo = order.begin() + std::ptrdiff_t(first), hi = order.begin() + start[b];
        auto byKey = [&](std::uint32_t u, std::uint32_t v) { return keys[u] < keys[v] || (keys[u] == keys[v] && u < v); };
        if (!std::is_sorted(lo, hi, byKey)) std::sort(lo, hi, byKey);
        for (std::size_t e = first; e < start[b]; ++e) {
            const std::uint32_t i = order[e];
            if (e == first || keys[i] != cells.back().key) cells.push_back({keys[i], std::uint32_t(e), 0});
            cells.back().end = std::uint32_t(e + 1);
            m_nodes[e] = {points[i], i};
        }
    }
    // The cells into a table at most half full.
    m_cellCount = cells.size();
    m_table.assign(std::bit_ceil(2 * cells.size()), {EmptyKey, 0, 0});
    m_tableMask = m_table.size() - 1;
    for (const Cell& c : cells) {
        std::uint64_t s = mixBits(c.key) & m_tableMask;
        while (m_table[s].key != EmptyKey) s = (s + 1) & m_tableMask;
        m_table[s] = c;
    }
}

} // namespace store
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HashGridStore)
