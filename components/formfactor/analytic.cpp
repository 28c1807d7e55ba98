// formfactor "analytic" — Lambert's closed form for a differential area and a polygon,
// averaged over points of the emitting element, times a visibility estimate.
//
//   F_ij ≈ (1/n) Σ_x F(dA_x → P_j) · V̂(x, P_j)
//
// over n = points² points x of element i (the centres of points² equal sub-cells: the
// midpoint rule, error O(h²) in the sub-cell size h). F(dA → P) is exact
// for an unoccluded polygon (Lambert 1760; clipped to the hemisphere above x as Baum,
// Rushmeier & Winget 1989 require) and bounded by 1, so it stays finite however close
// two elements come (touching and coincident elements included). V̂ is the fraction of
// visibility_samples shadow rays from x to jittered points of P_j that arrive; with 0
// samples nothing occludes. Partly occluded pairs are approximated (Baum et al. use the
// hemi-cube for their visibility); unoccluded ones are exact up to the midpoint rule.
// In a closed enclosure the point form factors of one x sum to 1 exactly (the polygons
// tile the hemisphere), so rows sum to 1 up to round-off.
//
// Unequal areas: the quadrature is accurate on an element small against its distance to
// the other, poor on a large one (one point on a 10 m floor facing a 1 cm tile is 30
// times off). With reciprocity (default) each pair is therefore computed from its
// smaller element and the other direction follows from A_i F_ij = A_j F_ji, which then
// holds exactly; rows of a mesh with elements of different sizes no longer sum to
// exactly 1 in a closed enclosure (they do for equal elements, where nothing changes).
//
// Parameters:
//   points              int (default 1, 1..16)  quadrature points per side of element i
//   visibility_samples  int (default 4, >= 0)   shadow rays per point (0: unoccluded)
//   reciprocity         bool (default true)     compute each pair from its smaller element
//
// Reference: D. R. Baum, H. E. Rushmeier, J. M. Winget, "Improving Radiosity Solutions
// Through the Use of Analytically Determined Form-Factors", SIGGRAPH 1989.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/radiosity_geometry.hpp"

namespace effigi {
namespace {

class AnalyticFormFactor final : public Implements<IFormFactor> {
public:
    static Schema schema() {
        Schema s("formfactor", "analytic",
                 "Lambert's point-to-polygon form factor, averaged over points of the element, with shadow rays.");
        s.cite("Baum, Rushmeier & Winget, Improving Radiosity Solutions Through the Use of Analytically "
               "Determined Form-Factors, SIGGRAPH 1989");
        s.integer("points", 1, "Quadrature points per side of the emitting element (midpoint rule)").range(1, 16);
        s.integer("visibility_samples", 4, "Shadow rays per quadrature point; 0 assumes no occlusion").range(0, 1e6);
        s.boolean("reciprocity", true, "Compute each pair on its smaller element; the other way by A_i F_ij = A_j F_ji");
        return s;
    }

    explicit AnalyticFormFactor(const Properties& p)
        : m_points(int(p.getInt("points"))), m_visibility(int(p.getInt("visibility_samples"))),
          m_reciprocity(p.getBool("reciprocity")) {}

    void prepare(const FormFactorContext& context) override { m_ctx = context; }
    const FormFactorContext& context() const override { return m_ctx; }

    double formFactor(std::uint32_t i, std::uint32_t j) const override {
        const IMesh& mesh = *m_ctx.mesh;
        if (!canExchange(mesh, i, j)) return 0.0;
        float ai = mesh.elements()[i].area, aj = mesh.elements()[j].area;
        if (m_reciprocity && aj < ai) return std::min(1.0, fromPoints(j, i) * double(aj) / double(ai));
        return fromPoints(i, j);
    }

private:
    /// Quadrature over element i of the point form factor to element j.
    double fromPoints(std::uint32_t i, std::uint32_t j) const {
        const IMesh& mesh = *m_ctx.mesh;
        const MeshElement& a = mesh.elements()[i];
        const MeshElement& b = mesh.elements()[j];
        Polygon poly = elementPolygon(mesh, j);
        Vector3d na(a.n), nb(b.n);
        PCG32 rng(mixBits((std::uint64_t(i) << 32 | j) ^ mixBits(m_ctx.seed)), 0x5bd1e995u);
        int strata = std::max(1, int(std::ceil(std::sqrt(double(m_visibility)))));
        double sum = 0.0;
        for (int q = 0; q < m_points * m_points; ++q) {
            Point3f x = quadraturePoint(mesh, i, q);
            double f = pointToPolygonFormFactor(Vector3d(x), na, poly, nb);
            if (f > 0.0 && m_visibility > 0 && m_ctx.visibility) {
                int seen = 0;
                for (int k = 0; k < m_visibility; ++k) {
                    Point2f v((float(k % strata) + rng.nextFloat()) / float(strata),
                              (float((k / strata) % strata) + rng.nextFloat()) / float(strata));
                    Point3f y = sampleElement(mesh, j, v);
                    seen += mutuallyVisible(*m_ctx.visibility, x, a.n, y, b.n) ? 1 : 0;
                }
                f *= double(seen) / double(m_visibility);
            }
            sum += f;
        }
        return std::clamp(sum / double(m_points * m_points), 0.0, 1.0);
    }

    /// Quadrature point q of element i: the centre of cell q of a points × points grid
    /// over the parallelogram, or the centroid of sub-triangle q of the triangle cut into
    /// points² (rows of "up" and "down" triangles, as the mesh cuts its triangle patches).
    Point3f quadraturePoint(const IMesh& mesh, std::uint32_t i, int q) const {
        const MeshElement& e = mesh.elements()[i];
        std::span<const Point3f> v = mesh.vertices();
        const Point3f& p0 = v[e.vertices[0]];
        const float k = float(m_points);
        if (e.corners() == 4) {
            float s = (float(q % m_points) + 0.5f) / k, t = (float(q / m_points) + 0.5f) / k;
            return p0 + s * (v[e.vertices[1]] - p0) + t * (v[e.vertices[3]] - p0);
        }
        int row = 0, left = q;  // row r holds 2 (points − r) − 1 sub-triangles
        while (left >= 2 * (m_points - row) - 1) left -= 2 * (m_points - row) - 1, ++row;
        float c = left % 2 ? 2.f / 3.f : 1.f / 3.f;
        float s = (float(left / 2) + c) / k, t = (float(row) + c) / k;
        return p0 + s * (v[e.vertices[1]] - p0) + t * (v[e.vertices[2]] - p0);
    }

    int m_points, m_visibility;
    bool m_reciprocity;
    FormFactorContext m_ctx;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::AnalyticFormFactor)
