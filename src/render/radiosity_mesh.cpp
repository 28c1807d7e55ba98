// Meshing for radiosity (effigi/render/radiosity_mesh.hpp): shapes -> planar patches ->
// elements and welded vertices.
#include "effigi/render/radiosity_mesh.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"

#include <cmath>
#include <unordered_map>

namespace effigi {

RadiosityMesh::RadiosityMesh(const RadiosityMeshOptions& options)
    : m_options(options), m_bins(options.bins, LambdaMin, LambdaMax) {}

namespace {

/// Dual basis of (e1, e2) in their plane: d1·e1 = 1, d1·e2 = 0, d2·e1 = 0, d2·e2 = 1.
void dualBasis(RadiosityMesh::Patch& p) {
    double a = dot(p.e1, p.e1), b = dot(p.e1, p.e2), c = dot(p.e2, p.e2), det = a * c - b * b;
    if (!(det > 0.0)) return;
    p.d1 = Vector3f((c * Vector3d(p.e1) - b * Vector3d(p.e2)) / det);
    p.d2 = Vector3f((a * Vector3d(p.e2) - b * Vector3d(p.e1)) / det);
}

/// Whether triangles t and u form a parallelogram; if so, fill the quad patch.
bool pairUp(const TriangleMesh& m, std::size_t t, std::size_t u, float eps, RadiosityMesh::Patch& patch) {
    Point3f a[3], b[3];
    m.triangle(t, a[0], a[1], a[2]);
    m.triangle(u, b[0], b[1], b[2]);
    auto same = [&](const Point3f& p, const Point3f& q) { return maxAbsComponent(p - q) <= eps; };
    int sharedA[3] = {-1, -1, -1}, shared = 0;  // for each corner of t: matching corner of u
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (same(a[i], b[j])) {
                sharedA[i] = j;
                ++shared;
            }
    if (shared != 2) return false;
    int ia = sharedA[0] < 0 ? 0 : sharedA[1] < 0 ? 1 : 2;  // t's corner not shared
    int ib = 3 - sharedA[(ia + 1) % 3] - sharedA[(ia + 2) % 3];
    Vector3f na = cross(a[1] - a[0], a[2] - a[0]), nb = cross(b[1] - b[0], b[2] - b[0]);
    float la = length(na), lb = length(nb);
    if (!(la > 0.f && lb > 0.f) || dot(na, nb) < (1.f - 1e-5f) * la * lb) return false;
    // t = (pA, x, y) counter-clockwise: the quad is pA, x, pB, y with pB = x + y − pA.
    const Point3f& pA = a[ia];
    const Point3f& x = a[(ia + 1) % 3];
    const Point3f& y = a[(ia + 2) % 3];
    if (!same(b[ib], x + y - pA)) return false;
    patch.quad = true;
    patch.corner[0] = pA;
    patch.corner[1] = x;
    patch.corner[2] = b[ib];
    patch.corner[3] = y;
    patch.o = pA;
    patch.e1 = x - pA;
    patch.e2 = y - pA;
    patch.n = na / la;
    return true;
}

/// The point k/n of the way along an edge, computed from its endpoints in a canonical
/// order so that two patches sharing the edge get bitwise the same point (no cracks).
Point3f alongEdge(Point3f p, Point3f q, std::uint32_t k, std::uint32_t n) {
    if (q.x < p.x || (q.x == p.x && (q.y < p.y || (q.y == p.y && q.z < p.z)))) {
        std::swap(p, q);
        k = n - k;
    }
    if (k == 0) return p;
    if (k == n) return q;
    return (float(n - k) * p + float(k) * q) / float(n);
}

std::uint64_t countElements(const std::vector<RadiosityMesh::Patch>& patches, float edge) {
    std::uint64_t n = 0;
    for (const auto& p : patches) {
        if (p.quad) {
            n += std::uint64_t(std::max(1.f, std::ceil(length(p.e1) / edge))) *
                 std::uint64_t(std::max(1.f, std::ceil(length(p.e2) / edge)));
        } else {
            float longest = std::max({length(p.e1), length(p.e2), length(p.e2 - p.e1)});
            auto k = std::uint64_t(std::max(1.f, std::ceil(longest / edge)));
            n += k * k;
        }
    }
    return n;
}

} // namespace

void RadiosityMesh::build(std::span<const IShape* const> shapes) {
    m_patches.clear();
    m_shapeIndex.clear();
    m_triangleStart.assign(shapes.size() + 1, 0);
    m_trianglePatch.clear();
    for (std::uint32_t s = 0; s < shapes.size(); ++s) {
        const IShape* shape = shapes[s];
        m_shapeIndex[shape] = s;
        m_triangleStart[s] = m_trianglePatch.size();
        const TriangleMesh* tm = shape->mesh();
        const IBSDF* bsdf = shape->bsdf();
        bool diffuse = bsdf && !bsdf->isPureSpecular();
        if (!diffuse && !shape->emitter()) {
            m_triangleStart[s + 1] = m_trianglePatch.size();
            continue;  // specular only: an occluder, traced by two-pass renderers
        }
        if (!tm) {
            log::warn("radiosity: {} is not a triangle mesh and is not meshed; it only occludes",
                      shape->typeName().empty() ? std::string("a shape") : shape->typeName());
            m_triangleStart[s + 1] = m_trianglePatch.size();
            continue;
        }
        std::size_t n = tm->triangleCount(), first = m_trianglePatch.size();
        m_trianglePatch.resize(first + n, NoPatch);
        float eps = 1e-6f * std::max(maxAbsComponent(tm->bbox().max), maxAbsComponent(tm->bbox().min));
        for (std::size_t t = 0; t < n;) {
            Patch p;
            p.shape = s;
            p.tri[0] = p.tri[1] = std::uint32_t(t);
            std::size_t used = 1;
            if (t + 1 < n && pairUp(*tm, t, t + 1, eps, p)) {
                p.tri[1] = std::uint32_t(t + 1);
                used = 2;
            } else {
                Point3f p0, p1, p2;
                tm->triangle(t, p0, p1, p2);
                p.corner[0] = p0;
                p.corner[1] = p1;
                p.corner[2] = p2;
                p.o = p0;
                p.e1 = p1 - p0;
                p.e2 = p2 - p0;
                Vector3f nn = cross(p.e1, p.e2);
                float l = length(nn);
                if (!(l > 0.f)) {  // degenerate: no area, nothing to mesh
                    t += 1;
                    continue;
                }
                p.n = nn / l;
            }
            dualBasis(p);
            for (std::size_t k = 0; k < used; ++k) m_trianglePatch[first + t + k] = std::uint32_t(m_patches.size());
            m_patches.push_back(p);
            t += used;
        }
        m_triangleStart[s + 1] = m_trianglePatch.size();
    }
    if (m_patches.empty()) fail("radiosity: the scene has no diffuse or emitting triangle-mesh surface to mesh");

    // The edge length: given, or the largest count not above the target (bisection in log L).
    float longest = 0.f;
    for (const auto& p : m_patches) longest = std::max({longest, length(p.e1), length(p.e2), length(p.e2 - p.e1)});
    float edge = m_options.maxEdge;
    if (!(edge > 0.f)) {
        std::uint64_t target = std::max<std::uint64_t>(m_options.targetElements, 1);
        float lo = longest * 1e-5f, hi = longest * 1.0001f;  // count(hi) = #patches
        for (int it = 0; it < 60 && countElements(m_patches, lo) <= target; ++it) lo *= 0.5f;
        for (int it = 0; it < 60; ++it) {
            float mid = std::sqrt(lo * hi);
            (countElements(m_patches, mid) > target ? lo : hi) = mid;
        }
        edge = hi;
    }
    std::uint64_t count = countElements(m_patches, edge);
    if (count > 0xfffffff0ull) fail("radiosity: {} elements are too many (edge length {})", count, edge);
    m_edge = edge;
    subdivide(m_patches, edge);
    weld();
    evaluateMaterials(shapes);
    m_radiosity = m_emission;
    radiosityChanged();
}

void RadiosityMesh::subdivide(std::vector<Patch>& patches, float edge) {
    m_elements.clear();
    m_vertices.clear();
    m_vertexNormals.clear();
    for (Patch& p : patches) {
        p.firstElement = std::uint32_t(m_elements.size());
        p.firstVertex = std::uint32_t(m_vertices.size());
        if (p.quad) {
            p.nu = std::uint32_t(std::max(1.f, std::ceil(length(p.e1) / edge)));
            p.nv = std::uint32_t(std::max(1.f, std::ceil(length(p.e2) / edge)));
            const Point3f* c = p.corner;
            for (std::uint32_t b = 0; b <= p.nv; ++b)
                for (std::uint32_t a = 0; a <= p.nu; ++a) {
                    Point3f v;
                    if (b == 0) v = alongEdge(c[0], c[1], a, p.nu);
                    else if (b == p.nv) v = alongEdge(c[3], c[2], a, p.nu);
                    else if (a == 0) v = alongEdge(c[0], c[3], b, p.nv);
                    else if (a == p.nu) v = alongEdge(c[1], c[2], b, p.nv);
                    else v = p.o + (float(a) / float(p.nu)) * p.e1 + (float(b) / float(p.nv)) * p.e2;
                    m_vertices.push_back(v);
                }
            float area = length(cross(p.e1, p.e2)) / float(p.nu * p.nv);
            auto vid = [&](std::uint32_t a, std::uint32_t b) { return p.firstVertex + b * (p.nu + 1) + a; };
            for (std::uint32_t b = 0; b < p.nv; ++b)
                for (std::uint32_t a = 0; a < p.nu; ++a) {
                    MeshElement e;
                    e.vertices = {vid(a, b), vid(a + 1, b), vid(a + 1, b + 1), vid(a, b + 1)};
                    e.centre = p.o + ((float(a) + 0.5f) / float(p.nu)) * p.e1 + ((float(b) + 0.5f) / float(p.nv)) * p.e2;
                    e.n = p.n;
                    e.area = area;
                    e.shape = p.shape;
                    m_elements.push_back(e);
                }
        } else {
            float longest = std::max({length(p.e1), length(p.e2), length(p.e2 - p.e1)});
            std::uint32_t k = std::uint32_t(std::max(1.f, std::ceil(longest / edge)));
            p.nu = p.nv = k;
            // Vertex (i, j), i + j ≤ k, at o + (i e1 + j e2) / k; rows of constant j.
            auto vid = [&](std::uint32_t i, std::uint32_t j) { return p.firstVertex + j * (k + 1) - j * (j - 1) / 2 + i; };
            const Point3f* c = p.corner;
            for (std::uint32_t j = 0; j <= k; ++j)
                for (std::uint32_t i = 0; i + j <= k; ++i) {
                    Point3f v;
                    if (j == 0) v = alongEdge(c[0], c[1], i, k);
                    else if (i == 0) v = alongEdge(c[0], c[2], j, k);
                    else if (i + j == k) v = alongEdge(c[1], c[2], j, k);
                    else v = p.o + (float(i) / float(k)) * p.e1 + (float(j) / float(k)) * p.e2;
                    m_vertices.push_back(v);
                }
            float area = 0.5f * length(cross(p.e1, p.e2)) / float(k * k);
            for (std::uint32_t j = 0; j < k; ++j)
                for (std::uint32_t i = 0; i + j < k; ++i)
                    for (int down = 0; down < 2; ++down) {
                        if (down && i + j + 1 >= k) continue;  // the last cell of a row has no "down" half
                        MeshElement e;
                        if (!down) e.vertices = {vid(i, j), vid(i + 1, j), vid(i, j + 1), MeshElement::NoVertex};
                        else e.vertices = {vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1), MeshElement::NoVertex};
                        e.centre = (m_vertices[e.vertices[0]] + m_vertices[e.vertices[1]] + m_vertices[e.vertices[2]]) / 3.f;
                        e.n = p.n;
                        e.area = area;
                        e.shape = p.shape;
                        m_elements.push_back(e);
                    }
        }
        m_vertexNormals.resize(m_vertices.size(), p.n);
    }
}

void RadiosityMesh::weld() {
    // Merge vertices closer than q with normals within ~1°: a hash grid of cell q, each
    // vertex checked against the 27 cells around it.
    BBox3f box;
    for (const Point3f& v : m_vertices) box.expand(v);
    float q = 1e-5f * std::max(maxAbsComponent(box.max), maxAbsComponent(box.min)) + 1e-30f;
    struct CellHash {
        std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
            return std::size_t(mixBits(std::uint64_t(c[0]) * 73856093u ^ std::uint64_t(c[1]) * 19349663u ^
                                       std::uint64_t(c[2]) * 83492791u));
        }
    };
    std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>, CellHash> grid;
    std::vector<std::uint32_t> remap(m_vertices.size());
    std::vector<Point3f> verts;
    std::vector<Normal3f> normals;
    for (std::uint32_t v = 0; v < m_vertices.size(); ++v) {
        const Point3f& p = m_vertices[v];
        std::array<std::int64_t, 3> c{std::int64_t(std::floor(p.x / q)), std::int64_t(std::floor(p.y / q)),
                                      std::int64_t(std::floor(p.z / q))};
        std::uint32_t found = MeshElement::NoVertex;
        for (int dz = -1; dz <= 1 && found == MeshElement::NoVertex; ++dz)
            for (int dy = -1; dy <= 1 && found == MeshElement::NoVertex; ++dy)
                for (int dx = -1; dx <= 1 && found == MeshElement::NoVertex; ++dx) {
                    auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == grid.end()) continue;
                    for (std::uint32_t w : it->second)
                        if (maxAbsComponent(verts[w] - p) <= q && dot(normals[w], m_vertexNormals[v]) > 0.9998f) {
                            found = w;
                            break;
                        }
                }
        if (found == MeshElement::NoVertex) {
            found = std::uint32_t(verts.size());
            verts.push_back(p);
            normals.push_back(m_vertexNormals[v]);
            grid[c].push_back(found);
        }
        remap[v] = found;
    }
    m_vertices = std::move(verts);
    m_vertexNormals = std::move(normals);
    for (MeshElement& e : m_elements)
        for (int k = 0; k < e.corners(); ++k) e.vertices[k] = remap[e.vertices[k]];
    // Adjacency in compressed rows: the elements around each vertex.
    m_adjacencyStart.assign(m_vertices.size() + 1, 0);
    for (const MeshElement& e : m_elements)
        for (int k = 0; k < e.corners(); ++k) ++m_adjacencyStart[e.vertices[k] + 1];
    for (std::size_t v = 0; v < m_vertices.size(); ++v) m_adjacencyStart[v + 1] += m_adjacencyStart[v];
    m_adjacency.resize(m_adjacencyStart.back());
    std::vector<std::uint32_t> fill(m_adjacencyStart.begin(), m_adjacencyStart.end() - 1);
    for (std::uint32_t i = 0; i < m_elements.size(); ++i)
        for (int k = 0; k < m_elements[i].corners(); ++k) m_adjacency[fill[m_elements[i].vertices[k]]++] = i;
}

} // namespace effigi
