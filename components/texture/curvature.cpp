// texture "curvature" — the curvature of the surface under the lookup, as a texture
// (cavity and edge masks, wear, "pointiness"; Spectrum's shaders that query geometry).
//
// value = bias + scale · κ, with κ the mean curvature H (kind "mean"), the Gaussian
// curvature K ("gaussian"), or the larger or smaller principal curvature k1, k2 ("max",
// "min"), in inverse scene units (K: their square). Signs follow effigi::curvature
// (include/effigi/interfaces/ishape.hpp): positive where the surface bends away from its
// shading normal, so a sphere of radius r with outward normals reads H = 1/r, K = 1/r².
// With clamp = true (default) the value is clamped to [0, 1], a mask; with clamp = false
// only to ≥ 0 (a texture's value is a non-negative spectrum), with no upper bound.
//
// The curvature is asked of the shape on request (localGeometry(): ∂n/∂u, ∂n/∂v) and
// combined with ∂p/∂u, ∂p/∂v by the Weingarten equations; only renders that use this
// texture pay for it. Flat shapes (rectangles, disks, meshes without vertex normals)
// read bias; triangle meshes read the curvature of their interpolated vertex normals.
//
// Parameters:
//   kind   string  "mean"   mean | gaussian | max | min
//   scale  float   1        factor on the curvature (scene units, or their square)
//   bias   float   0        added after scaling
//   clamp  bool    true     clamp to [0, 1] (false: only to ≥ 0)
//
// Reference: M. do Carmo, Differential Geometry of Curves and Surfaces, 1976, §3-3
// (Weingarten equations); no Mitsuba 3 counterpart.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace effigi {
namespace {

enum class CurvatureKind { Mean, Gaussian, Max, Min };

class CurvatureTexture final : public Implements<ITexture> {
public:
    static Schema schema() {
        Schema s("texture", "curvature", "Surface curvature (mean, Gaussian, principal) under the lookup, scaled and biased.");
        s.cite("M. do Carmo, Differential Geometry of Curves and Surfaces, 1976, §3-3 (Weingarten equations)");
        s.string("kind", "mean", "Which curvature: mean, gaussian, max or min (principal)")
            .oneOf({"mean", "gaussian", "max", "min"});
        s.real("scale", 1.0, "Factor on the curvature (1/scene units; gaussian: 1/scene units²)");
        s.real("bias", 0.0, "Added after scaling");
        s.boolean("clamp", true, "Clamp the value to [0, 1] (false: only to ≥ 0)");
        // effigi-conform: the suite's probes lie on a flat quad, where every kind reads bias.
        s.addConformance({"default", {}});
        s.addConformance({"gaussian half", {{"kind", std::string("gaussian")}, {"scale", 0.5}, {"bias", 0.5}}});
        s.addConformance({"min below zero", {{"kind", std::string("min")}, {"bias", -1.0}}});
        s.addConformance({"max unclamped", {{"kind", std::string("max")}, {"scale", 1e3}, {"bias", 2.0}, {"clamp", false}}});
        return s;
    }

    explicit CurvatureTexture(const Properties& p)
        : m_scale(p.getFloat("scale")), m_bias(p.getFloat("bias")), m_clamp(p.getBool("clamp")) {
        const std::string kind = p.getString("kind");
        m_kind = kind == "gaussian" ? CurvatureKind::Gaussian
                 : kind == "max"    ? CurvatureKind::Max
                 : kind == "min"    ? CurvatureKind::Min
                                    : CurvatureKind::Mean;
        for (const char* name : {"scale", "bias"})
            if (!std::isfinite(p.getFloat(name)))
                failAt(p.whereOf(name), "{}: parameter '{}' must be finite", p.describe(), name);
    }

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths&) const override {
        return SampledSpectrum(value(si));
    }
    float evalFloat(const SurfaceInteraction& si) const override { return value(si); }

    float maxValue() const override { return m_clamp ? 1.f : std::numeric_limits<float>::max(); }
    /// The surface is unknown until a lookup: a mid value as the lobe-selection weight.
    float mean() const override { return 0.5f; }

private:
    float value(const SurfaceInteraction& si) const {
        const Curvature c = curvature(si, localGeometry(si));
        const float k = m_kind == CurvatureKind::Mean       ? c.mean
                        : m_kind == CurvatureKind::Gaussian ? c.gaussian
                        : m_kind == CurvatureKind::Max      ? c.k1
                                                            : c.k2;
        const float v = m_bias + m_scale * k;
        if (!(v > 0.f)) return 0.f;  // NaN too (scale 0 times an infinite curvature)
        return m_clamp ? std::min(v, 1.f) : std::min(v, std::numeric_limits<float>::max());
    }

    CurvatureKind m_kind = CurvatureKind::Mean;
    float m_scale, m_bias;
    bool m_clamp;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::CurvatureTexture)
