// IShape defaults: no analytic intersection, and solid-angle sampling by converting
// the area density, p_ω = p_A · d² / |cos θ_light| (from dω = |cos θ_light| dA / d²; Veach 1997, thesis).
#include "effigi/interfaces/ishape.hpp"

namespace effigi {

bool IShape::intersect(const Ray&, float&, Point2f&) const { return false; }

DirectionSample IShape::sampleDirection(const Point3f& ref, const Point2f& u) const {
    DirectionSample ds;
    PositionSample ps = samplePosition(u);
    static_cast<PositionSample&>(ds) = ps;
    ds.pdf = 0.f;
    Vector3f d = ps.p - ref;
    float d2 = dot(d, d);
    if (!(d2 > 0.f) || !(ps.pdf > 0.f)) return ds;
    ds.dist = std::sqrt(d2);
    ds.wi = d * (1.f / ds.dist);
    float cosLight = absDot(ps.n, ds.wi);
    if (!(cosLight > 0.f)) return ds;
    ds.pdf = ps.pdf * d2 / cosLight;
    if (!std::isfinite(ds.pdf)) ds.pdf = 0.f;
    return ds;
}

float IShape::pdfDirection(const Point3f& ref, const SurfaceInteraction& si) const {
    float a = area();
    if (!(a > 0.f)) return 0.f;
    // The geometry itself gives the direction back to ref (si.wo by contract).
    Vector3f d = ref - si.p;
    float d2 = dot(d, d);
    if (!(d2 > 0.f)) return 0.f;
    float cosLight = absDot(si.n, d) / std::sqrt(d2);
    if (!(cosLight > 0.f)) return 0.f;
    float pdf = d2 / (a * cosLight);
    return std::isfinite(pdf) ? pdf : 0.f;
}

} // namespace effigi
