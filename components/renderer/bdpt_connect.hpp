#pragma once
// One strategy (s, t) of bidirectional path tracing: the first s vertices of the light
// subpath joined to the first t of the camera subpath. s = 0 takes the camera subpath as
// it is (it hit a light); s = 1 samples a fresh point on a light toward the camera
// vertex (next-event estimation); t = 1 samples a fresh connection to the camera and
// lands anywhere on the film (light tracing); otherwise the two end vertices are joined by
// a shadow ray. Each strategy is weighted by the power heuristic over all strategies
// that could have produced the same path (Veach 1997, §10.2–10.3): the densities of the
// others follow from the ratios pdfRev / pdfFwd along the path, after the vertices at the
// connection have their reverse densities recomputed for this connection.
// Reference: E. Veach, PhD thesis, 1997, ch. 10; pbrt 3rd ed., §16.3.4–16.3.5.
#include "bdpt_paths.hpp"

#include <utility>

namespace effigi::bdpt {

/// Sets a value for the rest of the scope and restores it afterwards.
template <typename T>
class Scoped {
public:
    Scoped() = default;
    Scoped(T* target, T value) : m_target(target) {
        if (m_target) m_saved = std::exchange(*m_target, std::move(value));
    }
    Scoped(const Scoped&) = delete;
    Scoped& operator=(Scoped&& o) noexcept {
        std::swap(m_target, o.m_target);
        std::swap(m_saved, o.m_saved);
        return *this;
    }
    ~Scoped() {
        if (m_target) *m_target = std::move(m_saved);
    }

private:
    T* m_target = nullptr;
    T m_saved{};
};

/// Power-heuristic weight of strategy (s, t) for the path light[0..s) + camera[0..t), where
/// `sampled` replaces the vertex that strategy sampled afresh (s = 1: the light point;
/// t = 1: the camera point).
inline float misWeight(const Context& ctx, Vertex* light, Vertex* camera, const Vertex& sampled, int s, int t,
                       const SampledWavelengths& lambda) {
    if (s + t == 2) return 1.f;
    auto remap = [](float f) { return f != 0.f ? f * f : 1.f; };
    Vertex* qs = s > 0 ? &light[s - 1] : nullptr;
    Vertex* pt = t > 0 ? &camera[t - 1] : nullptr;
    Vertex* qsMinus = s > 1 ? &light[s - 2] : nullptr;
    Vertex* ptMinus = t > 1 ? &camera[t - 2] : nullptr;

    Scoped<Vertex> swapped;
    if (s == 1) swapped = Scoped<Vertex>(qs, sampled);
    else if (t == 1) swapped = Scoped<Vertex>(pt, sampled);
    // The connection's end vertices scatter diffusely or glossily (connectible).
    Scoped<bool> d1(&pt->delta, false), d2(qs ? &qs->delta : nullptr, false);
    Scoped<float> r1(&pt->pdfRev, s > 0 ? ctx.pdf(*qs, qsMinus, *pt, lambda) : ctx.pdfLightOrigin(*pt));
    Scoped<float> r2;
    if (ptMinus) r2 = Scoped<float>(&ptMinus->pdfRev, s > 0 ? ctx.pdf(*pt, qs, *ptMinus, lambda) : ctx.pdfLight(*pt, *ptMinus));
    Scoped<float> r3, r4;
    if (qs) r3 = Scoped<float>(&qs->pdfRev, ctx.pdf(*pt, ptMinus, *qs, lambda));
    if (qsMinus) r4 = Scoped<float>(&qsMinus->pdfRev, ctx.pdf(*qs, pt, *qsMinus, lambda));

    // Strategies with more light vertices (walking the camera subpath back) and with more
    // camera vertices (walking the light subpath back); a delta vertex at either end of
    // their connecting segment makes a strategy impossible.
    float sum = 0.f, ri = 1.f;
    for (int i = t - 1; i > 0; --i) {
        ri *= remap(camera[i].pdfRev) / remap(camera[i].pdfFwd);
        if (!camera[i].delta && !camera[i - 1].delta) sum += ri;
    }
    ri = 1.f;
    for (int i = s - 1; i >= 0; --i) {
        ri *= remap(light[i].pdfRev) / remap(light[i].pdfFwd);
        bool deltaBefore = i > 0 ? light[i - 1].delta : light[0].isDeltaLight();
        if (!light[i].delta && !deltaBefore) sum += ri;
    }
    return 1.f / (1.f + sum);
}

/// The weighted contribution of strategy (s, t); for t = 1 the film position it lands on
/// (full-film pixels) is written to pFilm.
inline SampledSpectrum connect(const Context& ctx, Vertex* light, Vertex* camera, int s, int t, ISampler& sampler,
                               const SampledWavelengths& lambda, Point2f& pFilm) {
    SampledSpectrum L(0.f);
    Vertex sampled;
    if (s == 0) {
        const Vertex& pt = camera[t - 1];
        if (pt.type == VertexType::Surface && pt.si.emitter) L = pt.beta * pt.si.emitter->eval(pt.si, lambda);
    } else if (t == 1) {
        const Vertex& qs = light[s - 1];
        Point2f u = sampler.get2D();
        CameraImportanceSample cs;
        if (!qs.connectible() || !ctx.camera.sampleDirection(qs.p(), u, cs) || !(cs.pdf > 0.f) || cs.deltaDirection)
            return L;
        sampled = Vertex::camera(cs.pCamera, SampledSpectrum(cs.weight / cs.pdf));
        L = qs.beta * scatter(qs, sampled, lambda, TransportMode::Importance) * sampled.beta;
        if (qs.onSurface) L *= std::abs(dot(cs.wi, Vector3f(qs.ns())));
        if (!L.isBlack()) L *= ctx.transmittance(qs, sampled, lambda);
        pFilm = cs.pFilm;
    } else if (s == 1) {
        const Vertex& pt = camera[t - 1];
        float uSel = sampler.get1D();
        Point2f u = sampler.get2D();
        if (!pt.connectible() || ctx.lights.empty()) return L;
        const IEmitter* e = ctx.lights[std::min(std::size_t(uSel * float(ctx.lights.size())), ctx.lights.size() - 1)];
        EmitterSample es = e->sampleDirect(pt.p(), u, lambda);
        if (!(es.pdf > 0.f) || es.L.isBlack()) return L;
        float sel = ctx.lightPdf(e);
        sampled = Vertex::emitterPoint(e, es.p, es.n, es.L / (es.pdf * sel), 0.f);
        sampled.pdfFwd = ctx.pdfLightOrigin(sampled);
        L = pt.beta * scatter(pt, sampled, lambda, TransportMode::Radiance) * sampled.beta;
        if (pt.onSurface) L *= std::abs(dot(es.wi, Vector3f(pt.ns())));
        if (!L.isBlack()) L *= ctx.transmittance(pt, sampled, lambda);
    } else {
        const Vertex& qs = light[s - 1];
        const Vertex& pt = camera[t - 1];
        if (!qs.connectible() || !pt.connectible()) return L;
        L = qs.beta * scatter(qs, pt, lambda, TransportMode::Importance) *
            scatter(pt, qs, lambda, TransportMode::Radiance) * pt.beta;
        if (L.isBlack()) return L;
        Vector3f d = pt.p() - qs.p();
        float d2 = lengthSquared(d);
        if (!(d2 > 0.f)) return SampledSpectrum(0.f);
        d /= std::sqrt(d2);
        float g = std::abs(dot(Vector3f(qs.ns()), d)) * std::abs(dot(Vector3f(pt.ns()), d)) / d2;
        L *= g;
        if (!L.isBlack()) L *= ctx.transmittance(qs, pt, lambda);
    }
    if (L.isBlack()) return L;
    return L * misWeight(ctx, light, camera, sampled, s, t, lambda);
}

} // namespace effigi::bdpt
