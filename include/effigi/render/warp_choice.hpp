#pragma once
// WarpChoice — how a component (BSDF, emitter, camera) draws its directions or lens
// points: through a warp nested in its XML element, or by default through the
// compile-time code of a warp component (issue 14, "warps in use").
//
// Why a compile-time default rather than always creating the warp component: a scene
// that names no warp keeps an inlined call per sample and its exact results, because the
// default calls the same inline function of effigi/math/warp_functions.hpp as the warp
// component of the same name does (tests/test_warps_in_use.cpp checks it bit for bit).
// A nested warp (any IWarp, a plugin too) replaces it: sample(u) = warp.sample(u) and
// pdf(p) = warp.pdf(p), where a density that is not a finite positive number reads as 0,
// so that a caller skips the sample instead of dividing by it. The warp's domain must be
// of the default's kind (directions or points of the plane): otherwise loading fails
// with a one-line error at the warp's file:line. Whether the warp's support covers what
// the component needs (the hemisphere of a one-sided BSDF, a spot light's cone, the
// lens disk) is the component's matter: with a smaller support the estimate is biased,
// with a larger one only noisier.
#include "effigi/core/error.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

#include <cmath>
#include <string>

namespace effigi {

/// The code of the warp components as value types, the defaults a WarpChoice holds; each
/// names the component it equals and that component's domain kind.
namespace compiled_warp {

struct CosineHemisphere {  // warp "cosine_hemisphere"
    static constexpr WarpDomain::Kind Kind = WarpDomain::Kind::Sphere;
    Vector3f sample(const Point2f& u) const { return warp::squareToCosineHemisphere(u); }
    float pdf(const Vector3f& v) const { return warp::squareToCosineHemispherePdf(v); }
};

struct UniformSphere {  // warp "uniform_sphere"
    static constexpr WarpDomain::Kind Kind = WarpDomain::Kind::Sphere;
    Vector3f sample(const Point2f& u) const { return warp::squareToUniformSphere(u); }
    float pdf(const Vector3f& v) const { return warp::squareToUniformSpherePdf(v); }
};

struct UniformCone {  // warp "uniform_cone" with cos_cutoff = cosMax
    static constexpr WarpDomain::Kind Kind = WarpDomain::Kind::Sphere;
    float cosMax = 0.5f;
    Vector3f sample(const Point2f& u) const { return warp::squareToUniformCone(u, cosMax); }
    float pdf(const Vector3f& v) const { return warp::squareToUniformConePdf(v, cosMax); }
};

struct SquareToDisk {  // warp "square_to_disk"
    static constexpr WarpDomain::Kind Kind = WarpDomain::Kind::Plane;
    Vector3f sample(const Point2f& u) const {
        Point2f p = warp::squareToUniformDiskConcentric(u);
        return {p.x, p.y, 0.f};
    }
    float pdf(const Vector3f& p) const { return warp::squareToUniformDiskPdf({p.x, p.y}); }
};

} // namespace compiled_warp

template <typename Default> class WarpChoice {
public:
    /// Declares the optional nested warp in a component's schema; `doc` says what it
    /// samples and names the default.
    static void declare(Schema& s, std::string doc, const char* name = "warp") { s.child("warp", name, std::move(doc)); }

    /// The default alone (for a member set up once its parameters are known).
    explicit WarpChoice(Default fallback = {}) : m_default(fallback) {}
    /// The nested warp `name` of p, if any, else `fallback`.
    explicit WarpChoice(const Properties& p, Default fallback = {}, const char* name = "warp")
        : m_default(fallback), m_warp(p.get<IWarp>(name)) {
        if (m_warp && m_warp->domain().kind != Default::Kind)
            failAt(p.whereOf(name), "{}: the nested warp '{}' (parameter '{}') gives {}, not {}", p.describe(),
                   m_warp->typeName(), name, pointsOf(m_warp->domain().kind), pointsOf(Default::Kind));
    }

    /// Whether a nested warp replaces the default.
    bool nested() const { return bool(m_warp); }
    /// The nested warp, or null.
    const IWarp* nestedWarp() const { return m_warp.get(); }

    Vector3f sample(const Point2f& u) const { return m_warp ? m_warp->sample(u) : m_default.sample(u); }
    float pdf(const Vector3f& p) const {
        if (!m_warp) return m_default.pdf(p);
        float d = m_warp->pdf(p);
        return std::isfinite(d) && d > 0.f ? d : 0.f;
    }

private:
    static const char* pointsOf(WarpDomain::Kind k) {
        return k == WarpDomain::Kind::Sphere ? "directions" : "points of the plane";
    }

    Default m_default;
    Ref<IWarp> m_warp;  // null: the compiled-in default
};

} // namespace effigi
