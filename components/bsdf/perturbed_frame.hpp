#pragma once
// What `normalmap` and `bumpmap` share: a nested BSDF evaluated in a perturbed shading
// frame, as Mitsuba 3 does it. The adapter computes the perturbed frame P (relative to the
// incoming shading frame, whose normal is +z), maps wo and wi into it, evaluates the nested
// BSDF at a surface point whose shading frame is P, and then:
//   - the nested BSDF's foreshortening is in the perturbed frame, the renderer's in the
//     original one: f is multiplied by |cos θ'|/|cos θ| of the light's direction, so that
//     f·|cos θ| is Mitsuba's value (its BSDFs return f·cos). This is the shading-normal
//     BSDF of Veach 1997, §5.3: in importance mode it is the adjoint (the ratio of wo).
//     Like every shading-normal model it is not reciprocal and the adjoint may exceed
//     unit albedo when the normal is tilted, which is why effigi-conform sees flat maps
//     only; tests/test_bsdf_extra.cpp checks the tilted cases against their own laws.
//   - a direction w is kept only when it lies on the same side of the original and the
//     perturbed surface (w.z and (P⁻¹w).z have one sign): light may not leak through the
//     geometric side the shading frame pretends to face. Mitsuba tests this for the
//     sampled/next direction only; effigi tests both, as the adjoint needs.
//   - flip_invalid_normals (Mitsuba's default): when wo sees the back of the perturbed
//     normal, the normal is mirrored about the original one (tangential part negated).
//   - use_shadowing_function (Mitsuba's default): the light's direction w is attenuated by
//     the microfacet shadowing of Estevez et al. (Ray Tracing Gems, 2019, ch. 12), which
//     hides the "bump terminator": G = 2 / (1 + √(1 + α² tan²θ)), α² = min(1, tan²θn / 8).
// The flip depends on wo (the previous vertex, in both modes, as Mitsuba); the shadowing
// is on the light's side like the cosine ratio: wi in radiance mode, which is what Mitsuba
// does (it shadows the next direction in both modes; in importance mode effigi keeps the
// adjoint instead).
#include "nested_bsdf.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"

#include <optional>

namespace effigi {

/// Declares the parameters common to both adapters.
inline void declarePerturbedFrame(Schema& s) {
    s.child("bsdf", "bsdf", "The nested BSDF, evaluated in the perturbed shading frame").isRequired();
    s.boolean("flip_invalid_normals", true,
              "Mirror a perturbed normal the incident direction sees from behind (Mitsuba)");
    s.boolean("use_shadowing_function", true,
              "Attenuate by the Estevez et al. 2019 shadowing term against the bump terminator");
}

class PerturbedFrameBSDF : public Implements<IBSDF> {
public:
    explicit PerturbedFrameBSDF(const Properties& p)
        : m_nested(p.get<IBSDF>("bsdf")), m_flip(p.getBool("flip_invalid_normals")),
          m_shadow(p.getBool("use_shadowing_function")) {}

    std::uint32_t flags() const override { return m_nested->flags(); }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const override {
        Frame P = frame(si, wo);
        Vector3f pwo = P.toLocal(wo), pwi = P.toLocal(wi);
        if (!(sameSide(wo, pwo) && sameSide(wi, pwi))) return SampledSpectrum(0.f);
        return m_nested->f(perturbed(si, P), pwo, pwi, lambda, mode) * factor(P.n, wo, pwo, wi, pwi, mode);
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda,
              TransportMode mode) const override {
        Frame P = frame(si, wo);
        Vector3f pwo = P.toLocal(wo), pwi = P.toLocal(wi);
        if (!(sameSide(wo, pwo) && sameSide(wi, pwi))) return 0.f;
        return m_nested->pdf(perturbed(si, P), pwo, pwi, lambda, mode);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        Frame P = frame(si, wo);
        Vector3f pwo = P.toLocal(wo);
        if (!sameSide(wo, pwo)) return std::nullopt;
        std::optional<BSDFSample> bs = m_nested->sample(perturbed(si, P), pwo, uc, u, lambda, mode);
        if (!bs) return std::nullopt;
        Vector3f wi = normalize(P.toWorld(bs->wi));
        if (!sameSide(wi, bs->wi)) return std::nullopt;
        bs->f *= factor(P.n, wo, pwo, wi, bs->wi, mode);
        bs->wi = wi;
        return bs;
    }

protected:
    /// The perturbed frame in the local coordinates of si.shading (wo: the incident
    /// direction there, for flip_invalid_normals).
    virtual Frame frame(const SurfaceInteraction& si, const Vector3f& wo) const = 0;

    /// The frame of a perturbed normal n (local): n mirrored if wo sees its back (when
    /// enabled), the tangent `s` made orthogonal to it. A degenerate n keeps the original frame.
    Frame completeFrame(Vector3f n, const Vector3f& wo, const Vector3f& s) const {
        float len = length(n);
        if (!(len > 1e-6f) || !std::isfinite(len)) return Frame();
        n /= len;
        if (m_flip && wo.z * dot(wo, n) <= 0.f) n = Vector3f(-n.x, -n.y, n.z);
        Vector3f ts = s - n * dot(n, s);
        float tl = length(ts);
        if (!(tl > 1e-6f)) return Frame(n);
        ts /= tl;
        return Frame(ts, cross(n, ts), n);
    }

private:
    static bool sameSide(const Vector3f& w, const Vector3f& pw) { return w.z * pw.z > 0.f; }

    /// si with its shading frame replaced by P (expressed in world space).
    static SurfaceInteraction perturbed(const SurfaceInteraction& si, const Frame& P) {
        SurfaceInteraction psi = si;
        psi.shading = Frame(si.toWorld(P.s), si.toWorld(P.t), si.toWorld(P.n));
        return psi;
    }

    /// What multiplies the nested f: the cosine ratio that turns the nested BSDF's
    /// foreshortening (perturbed frame) into the renderer's (original frame), and the
    /// shadowing, both on the light's side: wi in radiance mode, wo in importance mode
    /// (the adjoint, Veach 1997 §5.3).
    float factor(const Vector3f& n, const Vector3f& wo, const Vector3f& pwo, const Vector3f& wi,
                 const Vector3f& pwi, TransportMode mode) const {
        bool radiance = mode == TransportMode::Radiance;
        const Vector3f& light = radiance ? wi : wo;
        double ratio = std::abs(double(radiance ? pwi.z : pwo.z)) / std::abs(double(light.z));
        return float(std::min(ratio * shadowing(n, light), 1e30));
    }

    float shadowing(const Vector3f& n, const Vector3f& w) const {
        if (!m_shadow) return 1.f;
        auto tan2 = [](const Vector3f& v) {
            double c2 = double(v.z) * v.z;
            return c2 > 0.0 ? std::max(0.0, 1.0 - c2) / c2 : std::numeric_limits<double>::infinity();
        };
        double a2 = std::min(0.125 * tan2(n), 1.0), t2 = tan2(w);
        if (std::isinf(t2)) return a2 > 0.0 ? 0.f : 1.f;
        return float(2.0 / (1.0 + std::sqrt(1.0 + a2 * t2)));
    }

    Ref<IBSDF> m_nested;
    bool m_flip, m_shadow;
};

} // namespace effigi
