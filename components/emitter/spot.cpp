// emitter "spot" — a point light that shines into a cone, optionally through a slide.
//
// A point at the origin of to_world radiates intensity I [W/sr] around its local +z
// axis. Inside `beam_width` the intensity is full; between `beam_width` and
// `cutoff_angle` it falls off linearly in the ANGLE from the axis (Mitsuba 3's curve,
// not pbrt's smoothstep in cosθ); beyond the cutoff it is dark. An optional texture
// multiplies the intensity like a slide in a projector: the direction (x, y, z) in the
// light's frame reads the texture at uv = ½ + ½ (x, y) / (z · tan(cutoff)), so the
// cutoff cone touches the texture's edges. It is a delta light in position.
// Emitted rays (light tracing, bdpt, photon maps) leave in directions drawn through a
// warp (issue 14, effigi/render/warp_choice.hpp) in the light's frame (+z the axis): by
// default the compiled-in code of warp `uniform_cone` with cos_cutoff = cos(cutoff_angle);
// a nested `warp` (any warp onto the sphere of directions) replaces it in sampleEmission()
// and pdfEmission(). Beyond the cutoff the light is dark, so any warp covering the cone
// (e.g. `uniform_sphere`, or a wider `uniform_cone`) is unbiased.
//
// Parameters (Mitsuba 3's `spot`):
//   intensity     spectrum (illuminant, default 1)  intensity on the axis [W sr^-1]
//   texture       texture (optional)  emission profile across the cone
//   cutoff_angle  float in [0.5, 179.9] degrees (default 20)  where the cone ends
//   beam_width    float in [0, cutoff] degrees (default ¾ cutoff)  full-intensity core
//   to_world      transform  position (translation) and aim (local +z)
//   scale         float ≥ 0 (default 1)  factor on the intensity (effigi extension)
//   luminance     float ≥ 0 (optional)   scale the intensity to this luminous intensity Y
//   power         float ≥ 0 (optional)   scale the intensity to this radiant flux [W],
//                 Φ = ∫ falloff dω · ∫ I dλ (the texture not counted)
//   warp          nested warp (optional)  emission direction sampler; default uniform in the cone
//
// Reference: Mitsuba 3 `spot` (falloff curve); pbrt-v4 §12.1.3 (spotlights).
#include "delta_light.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/scene_range.hpp"
#include "effigi/render/warp_choice.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {
namespace {

using DirectionWarp = WarpChoice<compiled_warp::UniformCone>;

class SpotEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "spot", "Spot light: a point light limited to a cone with a soft edge.");
        s.cite("Mitsuba 3 'spot' emitter; M. Pharr, W. Jakob, G. Humphreys, PBRT 4th ed., §12.1.3");
        s.spectrum("intensity", 1.f, SpectrumKind::Illuminant, "Radiant intensity along the axis")
            .atLeast(0.0)
            .withUnit("W sr^-1");
        s.optional("texture", ParamType::Texture, "Emission profile projected across the cone (like a slide)");
        // Below 0.5° the cone's 1 − cos(cutoff) has fewer than ~12 significant bits in
        // float (and rounds to 0 below 0.02°, where the light went dark): refused.
        s.real("cutoff_angle", 20.0, "Angle from the axis where the light ends").range(0.5, 179.9).withUnit("deg");
        s.optional("beam_width", ParamType::Float, "Angle of the full-intensity core (default ¾ cutoff_angle)")
            .range(0.0, 179.9)
            .withUnit("deg");
        s.transform("to_world", "Position (translation) and aim (local +z) of the light");
        EmissionScale::declare(s, "Scale the intensity to this luminous intensity", "W sr^-1",
                               "Scale the intensity so that the light emits this flux (texture not counted)");
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule (noise only)");
        DirectionWarp::declare(s, "Emission direction sampler (a warp onto the sphere of directions, +z the axis); "
                                  "default: the code of warp `uniform_cone` with cos_cutoff = cos(cutoff_angle), "
                                  "compiled in");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp) and
        // tests/test_emitters_extra.cpp, extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"hard edge", {{"cutoff_angle", 30.0}, {"beam_width", 30.0}}});
        s.addConformance({"all ramp", {{"cutoff_angle", 30.0}, {"beam_width", 0.0}}});
        s.addConformance({"needle", {{"cutoff_angle", 0.5}}});
        s.addConformance({"hemisphere", {{"cutoff_angle", 90.0}, {"beam_width", 60.0}}});
        s.addConformance({"nearly isotropic", {{"cutoff_angle", 179.9}, {"beam_width", 179.9}}});
        return s;
    }

    explicit SpotEmitter(const Properties& p) : m_intensity(p.getSpectrum("intensity", SpectrumKind::Illuminant)) {
        Transform toWorld = p.getTransform("to_world");
        m_position = toWorld.point(Point3f(0.f));
        m_toLocal = toWorld.inverse();
        m_axis = toWorld.vector(Vector3f(0.f, 0.f, 1.f));
        if (!isFinite(m_position) || !isFinite(m_axis) || !(lengthSquared(m_axis) > 0.f))
            failAt(p.whereOf("to_world"), "{}: to_world must be finite and invertible", p.describe());
        if (!inSceneRange(m_position))
            failAt(p.whereOf("to_world"), "{}: the position is beyond effigi's coordinate range ±{:g}", p.describe(),
                   MaxSceneCoordinate);
        m_axis = normalize(m_axis);
        m_cutoff = degToRad(p.getFloat("cutoff_angle"));
        float beam = p.has("beam_width") ? degToRad(p.getFloat("beam_width")) : 0.75f * m_cutoff;
        if (beam > m_cutoff)
            failAt(p.whereOf("beam_width"), "{}: beam_width {} exceeds cutoff_angle {} degrees", p.describe(),
                   p.getFloat("beam_width"), p.getFloat("cutoff_angle"));
        m_cosCutoff = std::cos(m_cutoff);
        m_warp = DirectionWarp(p, compiled_warp::UniformCone{m_cosCutoff});
        m_beam = beam;
        // A hard edge (beam = cutoff) has no transition band: 0 keeps the ramp finite.
        m_invTransition = m_cutoff > beam ? 1.f / (m_cutoff - beam) : 0.f;
        m_coneSolidAngle = coneSolidAngle(beam, m_cutoff);
        if (p.has("texture")) {
            if (m_cutoff >= 0.5f * Pi)
                failAt(p.whereOf("cutoff_angle"), "{}: a textured spot light needs cutoff_angle < 90 degrees",
                       p.describe());
            m_texture = p.getTexture("texture", SpectrumKind::Reflectance);
            m_uvFactor = std::tan(m_cutoff);
        }
        EmissionScale emission(p, true, "intensity");
        m_intensity = m_intensity.scaled(emission.factor(m_intensity, m_coneSolidAngle, m_intensity.maxValue()));
        m_luminance = cie::luminance(m_intensity);
    }

    std::uint32_t flags() const override { return EmitterDeltaPosition; }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths& lambda) const override {
        return delta_light::sampleDirect(ref, m_position, [&](const Vector3f& d) { return emitted(d, lambda); });
    }

    EmissionSample sampleEmission(const Point2f&, const Point2f& uDir, const SampledWavelengths& lambda) const override {
        Vector3f local = m_warp.sample(uDir);
        Vector3f d = normalize(m_toLocal.inverse().vector(local));
        return delta_light::emissionSample(m_position, d, m_axis, m_warp.pdf(local), emitted(d, lambda));
    }

    /// Directions uniform in the cutoff cone about the axis (or the nested warp's, in the
    /// light's frame). The cone's density needs only cos θ = axis·d, read as it always was.
    bool pdfEmission(const Point3f&, const Normal3f&, const Vector3f& d, float& pdfPosition,
                     float& pdfDirection) const override {
        pdfPosition = 1.f;
        pdfDirection = m_warp.pdf(m_warp.nested() ? normalize(m_toLocal.vector(d)) : Vector3f(0.f, 0.f, dot(m_axis, d)));
        return true;
    }

    /// Φ = I · ∫ falloff dω (the texture's mean weighs a slide in).
    float power() const override {
        return m_luminance * m_coneSolidAngle * (m_texture ? m_texture->mean() : 1.f);
    }

private:
    /// ∫ falloff dω for a full core up to `beam` and a linear ramp in θ to `cutoff`:
    /// 2π [1 + (sin beam − sin cutoff) / (cutoff − beam)], → 2π (1 − cos cutoff) as the
    /// ramp vanishes.
    static float coneSolidAngle(float beam, float cutoff) {
        if (cutoff - beam < 1e-4f) return 2.f * Pi * (1.f - std::cos(cutoff));
        return 2.f * Pi * (1.f + (std::sin(beam) - std::sin(cutoff)) / (cutoff - beam));
    }

    /// Intensity toward the world direction d (unit, away from the light).
    SampledSpectrum emitted(const Vector3f& d, const SampledWavelengths& lambda) const {
        Vector3f local = m_toLocal.vector(d);
        float len = length(local);
        if (!(len > 0.f)) return SampledSpectrum(0.f);
        local /= len;
        // The angle from the axis by atan2 of the transverse and axial parts: acos(cos θ)
        // near θ = 0 resolves only ~0.02° in float, too coarse for a narrow cone's ramp.
        const float theta = std::atan2(std::sqrt(local.x * local.x + local.y * local.y), local.z);
        if (!(theta < m_cutoff)) return SampledSpectrum(0.f);
        float falloff = theta <= m_beam ? 1.f : (m_cutoff - theta) * m_invTransition;
        SampledSpectrum L = m_intensity.sample(lambda) * falloff;
        if (m_texture) {
            SurfaceInteraction si;
            si.p = m_position;
            si.uv = Point2f(0.5f + 0.5f * local.x / (local.z * m_uvFactor), 0.5f + 0.5f * local.y / (local.z * m_uvFactor));
            L *= m_texture->eval(si, lambda);
        }
        return L;
    }

    Spectrum m_intensity;
    Ref<ITexture> m_texture;
    Transform m_toLocal;
    Point3f m_position{0.f};
    Vector3f m_axis{0.f, 0.f, 1.f};
    float m_cutoff = 0.f, m_beam = 0.f, m_cosCutoff = 1.f, m_invTransition = 0.f, m_uvFactor = 1.f;
    float m_coneSolidAngle = 0.f, m_luminance = 0.f;
    DirectionWarp m_warp;  // the emission direction sampler, in the light's frame
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::SpotEmitter)
