// formfactor "hemicube" — Cohen & Greenberg's hemi-cube: a whole row F_i· at once by
// projecting the scene onto the five faces of a half cube around element i's centre.
//
// The top face (resolution² pixels) and four half side faces (resolution × resolution/2)
// are z-buffers of element ids. Pixel p at (x, y, 1) on the top face carries the delta
// form factor ΔA / (π (x² + y² + 1)²), a side pixel at height z the factor
// z ΔA / (π (x² + z² + 1)²); the tables are normalised to sum to 1, so the rows of a
// closed enclosure sum to exactly 1. F_ij is the sum over the pixels where j is the
// closest surface. Elements seen from behind and the triangles of shapes that are not
// meshed (mirrors, glass) are drawn as occluders; analytic shapes (spheres) cannot be
// rasterised and do not occlude (a warning says so). Geometry closer to the centre than
// 1e-6 √A_i (the near plane) is not seen: coincident elements do not exchange light.
//
// Error: the hemi-cube is a differential (point) form factor at the element centre —
// exact in the limit of small elements — plus the aliasing of the pixel grid: polygon
// edges cost at most about one pixel's delta form factor per pixel of projected edge,
// so the error of a large polygon falls as 1/resolution. Columns use reciprocity,
// F_ji = F_ij A_i / A_j (clamped to 1), as progressive refinement did with it.
//
// Parameters:
//   resolution  int (default 128, even, 8..4096)  pixels across the top face
//
// Reference: M. F. Cohen, D. P. Greenberg, "The Hemi-Cube: A Radiosity Solution for
// Complex Environments", SIGGRAPH 1985.
#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/frame.hpp"
#include "effigi/render/radiosity_geometry.hpp"
#include "hemicube_raster.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <set>

namespace effigi {
namespace {

using hemicube::None;
using hemicube::rasterPolygon;


struct Buffers {
    std::vector<std::uint32_t> ids;
    std::vector<float> depth;        // 1 / distance along the face axis; 0 = empty
    std::vector<Vector3f> local;     // mesh vertices in the hemi-cube frame (s, t, n)
    std::vector<Vector3f> occluders; // occluder triangle corners, same frame
    std::vector<double> sums;        // the row being summed
    std::uint32_t row = None;        // the row cached by formFactor()
    std::vector<float> cached;
};

class HemicubeFormFactor final : public Implements<IFormFactor> {
public:
    static Schema schema() {
        Schema s("formfactor", "hemicube", "Cohen & Greenberg's hemi-cube: z-buffered delta form factors, a row at a time.");
        s.cite("M. F. Cohen, D. P. Greenberg, The Hemi-Cube: A Radiosity Solution for Complex Environments, "
               "SIGGRAPH 1985");
        s.integer("resolution", 128, "Pixels across the top face (even); side faces are half as high").range(8, 4096);
        return s;
    }

    explicit HemicubeFormFactor(const Properties& p) : m_res(int(p.getInt("resolution"))) {
        if (m_res % 2) failAt(p.whereOf("resolution"), "{}: resolution must be even, got {}", p.describe(), m_res);
        const int half = m_res / 2;
        const double h = 2.0 / m_res, dA = h * h;
        m_top.resize(std::size_t(m_res) * m_res);
        m_side.resize(std::size_t(m_res) * half);
        double sum = 0.0;
        for (int y = 0; y < m_res; ++y)
            for (int x = 0; x < m_res; ++x) {
                double u = (x + 0.5) * h - 1.0, v = (y + 0.5) * h - 1.0, d = u * u + v * v + 1.0;
                sum += m_top[std::size_t(y) * m_res + x] = dA / (Pi * d * d);
            }
        for (int y = 0; y < half; ++y)
            for (int x = 0; x < m_res; ++x) {
                double u = (x + 0.5) * h - 1.0, z = (y + 0.5) * h, d = u * u + z * z + 1.0;
                double f = z * dA / (Pi * d * d);
                m_side[std::size_t(y) * m_res + x] = f;
                sum += 4.0 * f;
            }
        for (double& f : m_top) f /= sum;  // the discrete tables sum to 1 (analytically they do)
        for (double& f : m_side) f /= sum;
    }

    void prepare(const FormFactorContext& context) override {
        m_ctx = context;
        m_buffers.clear();
        m_occluders.clear();
        std::set<std::uint32_t> meshed;
        for (const MeshElement& e : m_ctx.mesh->elements()) meshed.insert(e.shape);
        for (std::uint32_t s = 0; s < m_ctx.shapes.size(); ++s) {
            if (meshed.count(s)) continue;
            const TriangleMesh* tm = m_ctx.shapes[s]->mesh();
            if (!tm) {
                log::warn("formfactor 'hemicube': {} is not a triangle mesh and does not occlude",
                          m_ctx.shapes[s]->typeName());
                continue;
            }
            for (std::size_t t = 0; t < tm->triangleCount(); ++t) {
                Point3f p0, p1, p2;
                tm->triangle(t, p0, p1, p2);
                m_occluders.insert(m_occluders.end(), {p0, p1, p2});
            }
        }
    }
    const FormFactorContext& context() const override { return m_ctx; }

    void row(std::uint32_t i, std::span<float> out) const override {
        std::fill(out.begin(), out.end(), 0.f);
        const IMesh& mesh = *m_ctx.mesh;
        const MeshElement& self = mesh.elements()[i];
        Buffers& buf = m_buffers.local();
        buf.sums.assign(out.size(), 0.0);  // summed in double: a row adds ~50k pixels
        Frame frame(self.n);
        auto toLocal = [&](const Point3f& p) { return frame.toLocal(p - self.centre); };
        std::span<const Point3f> verts = mesh.vertices();
        buf.local.resize(verts.size());
        for (std::size_t v = 0; v < verts.size(); ++v) buf.local[v] = toLocal(verts[v]);
        buf.occluders.resize(m_occluders.size());
        for (std::size_t k = 0; k < m_occluders.size(); ++k) buf.occluders[k] = toLocal(m_occluders[k]);
        const float zNear = 1e-6f * std::sqrt(self.area);  // the closest geometry it resolves

        for (int face = 0; face < 5; ++face) {
            const int height = face == 0 ? m_res : m_res / 2;
            buf.ids.assign(std::size_t(m_res) * height, None);
            buf.depth.assign(std::size_t(m_res) * height, 0.f);
            Vector3f poly[Polygon::MaxCorners];
            for (std::uint32_t j = 0; j < mesh.elementCount(); ++j) {
                if (j == i) continue;
                const MeshElement& e = mesh.elements()[j];
                int n = e.corners();
                for (int k = 0; k < n; ++k) poly[k] = onFace(face, buf.local[e.vertices[k]]);
                // Seen from behind (one-sided) it only occludes.
                std::uint32_t id = dot(e.n, self.centre - e.centre) > 0.f ? j : None;
                rasterPolygon(poly, n, zNear, face != 0, m_res, height, id, buf.ids.data(), buf.depth.data());
            }
            for (std::size_t k = 0; k + 2 < buf.occluders.size(); k += 3) {
                for (int c = 0; c < 3; ++c) poly[c] = onFace(face, buf.occluders[k + c]);
                rasterPolygon(poly, 3, zNear, face != 0, m_res, height, None, buf.ids.data(), buf.depth.data());
            }
            const std::vector<double>& table = face == 0 ? m_top : m_side;
            for (std::size_t p = 0; p < buf.ids.size(); ++p)
                if (buf.ids[p] != None) buf.sums[buf.ids[p]] += table[p];
        }
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = float(buf.sums[j]);
    }

    void column(std::uint32_t i, std::span<float> out) const override {
        row(i, out);
        const auto& el = m_ctx.mesh->elements();
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = std::min(1.f, out[j] * el[i].area / el[j].area);
    }

    double formFactor(std::uint32_t i, std::uint32_t j) const override {
        Buffers& buf = m_buffers.local();
        if (buf.row != i) {
            std::vector<float> r(m_ctx.mesh->elementCount());
            row(i, r);
            buf.cached = std::move(r);
            buf.row = i;
        }
        return buf.cached[j];
    }

private:
    /// A hemi-cube-frame point in face coordinates (x, y right and up on the face, z the
    /// distance along the face's axis). Face 0 looks along n; faces 1–4 along ±s, ±t,
    /// with y along n (only y ≥ 0 is on the face).
    static Vector3f onFace(int face, const Vector3f& p) {
        switch (face) {
        case 0: return {p.x, p.y, p.z};
        case 1: return {p.y, p.z, p.x};
        case 2: return {-p.y, p.z, -p.x};
        case 3: return {-p.x, p.z, p.y};
        default: return {p.x, p.z, -p.y};
        }
    }

    int m_res;
    std::vector<double> m_top, m_side;
    std::vector<Point3f> m_occluders;
    FormFactorContext m_ctx;
    mutable tbb::enumerable_thread_specific<Buffers> m_buffers;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HemicubeFormFactor)
