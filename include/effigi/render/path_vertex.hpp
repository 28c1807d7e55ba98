#pragma once
// The vertices of path space, as every bidirectional method records them (bdpt, pssmlt's
// bidirectional estimator; written by an IPathGenerator). A path of k segments has k + 1
// vertices x0 … xk and can be sampled by k + 2 strategies (s, t): s vertices traced from a
// light, t from the camera, joined by one connecting segment. Each vertex carries the
// subpath throughput `beta` up to it and two densities *per unit area* (Veach 1997,
// §10.2): pdfFwd, the density with which its own subpath produced it, and pdfRev, the
// density with which the opposite subpath would have produced it. Their ratios give
// every strategy's density relative to the one used, hence the MIS weights
// (components/renderer/bdpt_connect.hpp). Delta (specular) vertices cannot be connected; their densities are
// left 0, which the weight computation reads as "unchanged".
// Reference: E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD
// thesis, 1997, ch. 10; E. Lafortune, Y. Willems 1993; Pharr, Jakob, Humphreys,
// Physically Based Rendering, 3rd ed., §16.3.
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/render/interaction.hpp"

#include <cmath>
#include <cstdint>

namespace effigi {

enum class PathVertexType : std::uint8_t { Camera, Light, Surface };

struct PathVertex {
    PathVertexType type = PathVertexType::Surface;
    SampledSpectrum beta{0.f};
    /// Position and normals; for Camera and Light vertices only p and n are meaningful.
    SurfaceInteraction si;
    const IEmitter* light = nullptr;  ///< the emitter of a Light vertex
    bool delta = false;               ///< scattered by a delta lobe: no connection here
    bool onSurface = false;           ///< has a normal: cosines count at this vertex
    float pdfFwd = 0.f, pdfRev = 0.f;

    const Point3f& p() const { return si.p; }
    /// The emitter found here: a Light vertex's own, or the area light of a surface.
    const IEmitter* emitter() const { return type == PathVertexType::Light ? light : si.emitter; }
    bool isDeltaLight() const { return type == PathVertexType::Light && light->isDelta(); }
    /// Normal for the cosines of the geometry term: shading normal on surfaces.
    Normal3f ns() const { return type == PathVertexType::Surface ? Normal3f(si.shading.n) : si.n; }

    /// A strategy may end a subpath here and connect it to the other one.
    bool connectible() const {
        switch (type) {
        case PathVertexType::Camera: return true;
        case PathVertexType::Light: return !(light->flags() & EmitterDeltaDirection);
        case PathVertexType::Surface: return si.bsdf && !si.bsdf->isPureSpecular();
        }
        return false;
    }

    /// The area density at `next` of a solid-angle density pdfDir at this vertex.
    float toArea(float pdfDir, const PathVertex& next) const {
        Vector3f w = next.p() - p();
        float d2 = lengthSquared(w);
        if (!(d2 > 0.f)) return 0.f;
        float pdf = pdfDir / d2;
        if (next.onSurface) pdf *= std::abs(dot(next.si.n, w)) / std::sqrt(d2);
        return pdf;
    }

    static PathVertex camera(const Point3f& p, const SampledSpectrum& beta) {
        PathVertex v;
        v.type = PathVertexType::Camera;
        v.si.p = p;
        v.beta = beta;
        return v;
    }
    static PathVertex emitterPoint(const IEmitter* e, const Point3f& p, const Normal3f& n, const SampledSpectrum& beta,
                               float pdfFwd) {
        PathVertex v;
        v.type = PathVertexType::Light;
        v.light = e;
        v.si.p = p;
        v.si.n = n;
        v.onSurface = (e->flags() & EmitterSurface) != 0;
        v.beta = beta;
        v.pdfFwd = pdfFwd;
        return v;
    }
    static PathVertex surface(const SurfaceInteraction& si, const SampledSpectrum& beta) {
        PathVertex v;
        v.si = si;
        v.onSurface = true;
        v.beta = beta;
        return v;
    }
};

/// The adjoint correction of shading normals for importance transport,
/// |wo·ng · wi·ns| / |wo·ns · wi·ng| (Veach 1997, §5.3); wo and wi are world directions.
inline float shadingCorrection(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi) {
    float num = std::abs(dot(wo, si.n) * dot(wi, si.shading.n));
    float den = std::abs(dot(wo, si.shading.n) * dot(wi, si.n));
    return den > 0.f ? num / den : 0.f;
}

/// f at a surface vertex for light leaving toward `next`, arriving from si.wo's side; in
/// importance transport with the shading-normal correction.
inline SampledSpectrum scatter(const PathVertex& v, const PathVertex& next, const SampledWavelengths& lambda,
                               TransportMode mode) {
    Vector3f wi = normalize(next.p() - v.p());
    SampledSpectrum f = v.si.bsdf->f(v.si, v.si.toLocal(v.si.wo), v.si.toLocal(wi), lambda, mode);
    if (mode == TransportMode::Importance) f *= shadingCorrection(v.si, v.si.wo, wi);
    return f;
}

} // namespace effigi
