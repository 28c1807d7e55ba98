// warp "ggx_visible_normals" — GGX microfacet normals visible from a direction.
//
// Samples m with density D_wi(m) = G1(wi) max(0, wi·m) D(m) / cosθi per unit solid
// angle (the distribution of visible normals), where D is the anisotropic GGX normal
// distribution and G1 Smith's masking term. Rough BSDFs reflect or refract about such an
// m; sampling visible normals never wastes samples on back-facing microfacets. The map
// is a bijection from the square onto the visible normals, so it is invertible.
//
// Parameters:
//   alpha     float (default 0.3, in [1e-4, 4])     roughness αx (and αy unless alpha_v)
//   alpha_v   float (optional, in [1e-4, 4])        roughness αy: anisotropic GGX
//   incident  vector (default (0.5, 0, 0.866))      wi, normalised; must have z > 0
//
// Reference: E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4),
// 2018; B. Walter et al., "Microfacet Models for Refraction through Rough Surfaces",
// EGSR 2007. Math in effigi/math/warp_functions.hpp.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class GGXVisibleNormals final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "ggx_visible_normals",
                 "GGX microfacet normals visible from a direction wi (Heitz 2018); density G1 (wi·m) D / cosθi.");
        s.cite("E. Heitz, Sampling the GGX Distribution of Visible Normals, JCGT 7(4), 2018");
        s.real("alpha", 0.3, "GGX roughness αx (and αy unless alpha_v is given)").range(1e-4, 4.0);
        s.optional("alpha_v", ParamType::Float, "GGX roughness αy (anisotropic); default: alpha").range(1e-4, 4.0);
        s.vector("incident", Vector3f(0.5f, 0.f, 0.8660254f), "Direction wi the normals are seen from (z > 0)");
        s.addConformance({"smooth", {{"alpha", 0.05}}});
        s.addConformance({"rough", {{"alpha", 1.0}}});
        s.addConformance({"anisotropic", {{"alpha", 0.1}, {"alpha_v", 0.6}, {"incident", VectorValue{{0.3f, 0.6f, 0.5f}}}}});
        s.addConformance({"normal incidence", {{"alpha", 0.4}, {"incident", VectorValue{{0.f, 0.f, 1.f}}}}});
        s.addConformance({"grazing", {{"alpha", 0.5}, {"incident", VectorValue{{1.f, 0.f, 1e-3f}}}}});
        return s;
    }

    explicit GGXVisibleNormals(const Properties& p)
        : m_alphaX(p.getFloat("alpha")), m_alphaY(p.has("alpha_v") ? p.getFloat("alpha_v") : m_alphaX) {
        Vector3f wi = p.getVector("incident");
        float len = length(wi);
        if (!(len > 0.f) || !(wi.z > 0.f) || !isFinite(wi))
            failAt(p.whereOf("incident"), "{}: parameter 'incident' must be a finite vector with z > 0", p.describe());
        m_wi = wi / len;
    }

    WarpDomain domain() const override {
        return {WarpDomain::Kind::Sphere, {}, {},
                fmt::format("hemisphere of normals visible from ({:.3g}, {:.3g}, {:.3g})", m_wi.x, m_wi.y, m_wi.z)};
    }
    Vector3f sample(const Point2f& u) const override { return warp::squareToGGXVisibleNormal(m_wi, m_alphaX, m_alphaY, u); }
    float pdf(const Vector3f& m) const override { return warp::squareToGGXVisibleNormalPdf(m, m_wi, m_alphaX, m_alphaY); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& m) const override { return warp::ggxVisibleNormalToSquare(m, m_wi, m_alphaX, m_alphaY); }

private:
    float m_alphaX, m_alphaY;
    Vector3f m_wi{0.f, 0.f, 1.f};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::GGXVisibleNormals)
