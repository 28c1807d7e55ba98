#pragma once
// What ggx_visible_normals and beckmann_visible_normals share: the same warp (sample,
// pdf and inverse of the distribution of visible normals, effigi/render/microfacet.hpp)
// over two microfacet distributions, with the same parameters and conformance
// configurations. Each component file adds its schema's name, doc and citation.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/render/microfacet.hpp"

#include <fmt/format.h>

namespace effigi {

/// Parameters alpha, alpha_v, incident and the conformance configurations.
inline void declareVisibleNormalsParameters(Schema& s, const std::string& distribution) {
    s.real("alpha", 0.3, distribution + " roughness αx (and αy unless alpha_v is given)").range(1e-4, 4.0);
    s.optional("alpha_v", ParamType::Float, distribution + " roughness αy (anisotropic); default: alpha")
        .range(1e-4, 4.0);
    s.vector("incident", Vector3f(0.5f, 0.f, 0.8660254f), "Direction wi the normals are seen from (z > 0)");
    // alpha 0.1 for "smooth": narrower lobes need finer pdf integration per histogram cell,
    // which dominated the quick conformance run (28 s at 0.05) without checking more.
    s.addConformance({"smooth", {{"alpha", 0.1}}});
    s.addConformance({"rough", {{"alpha", 1.0}}});
    s.addConformance({"anisotropic", {{"alpha", 0.1}, {"alpha_v", 0.6}, {"incident", VectorValue{{0.3f, 0.6f, 0.5f}}}}});
    s.addConformance({"normal incidence", {{"alpha", 0.4}, {"incident", VectorValue{{0.f, 0.f, 1.f}}}}});
    s.addConformance({"grazing", {{"alpha", 0.5}, {"incident", VectorValue{{1.f, 0.f, 1e-3f}}}}});
    s.addConformance({"very rough, grazing", {{"alpha", 4.0}, {"incident", VectorValue{{0.f, 1.f, 1e-6f}}}}});
}

class VisibleNormalsWarp : public Implements<IWarp> {
public:
    VisibleNormalsWarp(MicrofacetType type, const Properties& p)
        : m_dist(type, p.getFloat("alpha"), p.has("alpha_v") ? p.getFloat("alpha_v") : p.getFloat("alpha")) {
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
    Vector3f sample(const Point2f& u) const override { return m_dist.sampleVisible(m_wi, u); }
    float pdf(const Vector3f& m) const override { return m_dist.visiblePdf(m_wi, m); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& m) const override { return m_dist.visibleToSquare(m_wi, m); }

private:
    MicrofacetDistribution m_dist;
    Vector3f m_wi{0.f, 0.f, 1.f};
};

} // namespace effigi
