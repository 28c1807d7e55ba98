// emitter "area" — a diffuse area light: makes any shape it is nested in glow.
//
// Every point of the shape emits the same radiance L into the hemisphere of its
// geometric normal; the back side is dark (ONE-SIDED, as Mitsuba 3's `area`). Direct
// lighting asks the shape for a point sampled by solid angle as seen from the shaded
// point (IShape::sampleDirection), so shapes with a better strategy than area
// sampling (spheres: the visible cone) give less noise for free. Emission sampling
// (light paths: ptracer, bdpt, photon maps) picks a point by area and a direction about
// the normal through a warp: by default the compile-time cosine warp, i.e. exactly the
// code the warp component `cosine_hemisphere` wraps (tests/test_warps_in_use.cpp checks
// that bit for bit); a nested `warp` (any IWarp onto the sphere of directions, e.g.
// `uniform_hemisphere` or a plugin) replaces it in sampleEmission() and pdfEmission()
// (effigi/render/warp_choice.hpp).
// The radiance is unchanged, so any warp covering the hemisphere is unbiased; a
// direction with z ≤ 0 about the normal is no sample (zero pdf, zero L).
//
// Parameters:
//   radiance   texture (illuminant spectrum, default 1)  emitted radiance [W m^-2 sr^-1]
//   scale      float ≥ 0 (default 1)  factor on the radiance
//   luminance  float ≥ 0 (optional)   scale a constant radiance to this luminance Y
//   power      float ≥ 0 (optional)   scale a constant radiance to this radiant flux [W],
//              Φ = π · A · ∫ L dλ over 360–830 nm (excludes luminance)
//   warp       nested warp (optional)  emission direction sampler; default cosine-weighted
//
// Reference: pbrt-v4 §12.2 (diffuse area lights); Glassner's Spectrum (any geometry emits).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/warp_choice.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"

namespace effigi {
namespace {

using DirectionWarp = WarpChoice<compiled_warp::CosineHemisphere>;

class AreaEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "area", "Diffuse area light: the shape it is nested in emits on its front side.");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §12.2");
        s.texture("radiance", 1.f, SpectrumKind::Illuminant,
                  "Emitted radiance (spectrum or texture), on the side of the geometric normal")
            .atLeast(0.0)
            .withUnit("W m^-2 sr^-1");
        EmissionScale::declare(s, "Scale a constant radiance to this luminance", "W m^-2 sr^-1",
                               "Scale a constant radiance so that the light emits the flux π · area · ∫L dλ");
        // Mitsuba's emitters take a light-selection weight; effigi picks lights by its own
        // rule, which changes noise only, never the expected image.
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule");
        DirectionWarp::declare(s, "Emission direction sampler (a warp onto the sphere of directions, about the "
                                  "normal); default: the code of warp `cosine_hemisphere`, compiled in");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp), which
        // nests the light in a square and a sphere; extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"tiny", {{"scale", 1e-6}}});
        s.addConformance({"huge", {{"radiance", 1e6}}});
        s.addConformance({"dark", {{"radiance", 0.0}}});
        s.addConformance({"power", {{"power", 10.0}}});
        // A nested warp is checked in tests/test_warps_in_use.cpp, not here: a configuration
        // holding one would load the warp module whenever this schema is asked for.
        return s;
    }

    explicit AreaEmitter(const Properties& p)
        : m_radiance(p.getTexture("radiance", SpectrumKind::Illuminant)), m_emission(p, true, "radiance"),
          m_warp(p) {
        if (m_emission.mode() != EmissionScale::Mode::Factor && !m_radiance->isConstant())
            failAt(p.whereOf(m_emission.mode() == EmissionScale::Mode::Power ? "power" : "luminance"),
                   "{}: 'luminance' and 'power' need a constant radiance, not a texture", p.describe());
        // power() only needs a bound for choosing among lights: the exact luminance of a
        // constant radiance, the texture's maximum otherwise.
        m_constant = m_radiance->isConstant();
        m_luminance = m_constant ? cie::luminance(radiance()) : m_radiance->maxValue();
        // The power target needs the shape's area: preprocess() sets the factor then.
        // The texture's upper bound is the radiance's peak (radiance() only reads one point).
        if (m_emission.mode() != EmissionScale::Mode::Power)
            m_scale = m_emission.factor(radiance(), 0.f, m_radiance->maxValue());
    }

    std::uint32_t flags() const override { return EmitterSurface; }

    void attach(const IShape* shape) override {
        // Only store it: the shape may not be fully built yet (no area, no BSDF).
        if (!shape) fail("{}: attach() needs a shape", name());
        if (m_shape && m_shape != shape) fail("{} cannot be nested in two shapes", name());
        m_shape = shape;
    }

    void preprocess(const BBox3f&) override {
        if (!m_shape) fail("area emitter must be nested in a shape");
        if (m_emission.mode() == EmissionScale::Mode::Power)
            m_scale = m_emission.factor(radiance(), Pi * m_shape->area(), m_radiance->maxValue());
    }

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        if (!(dot(si.n, si.wo) > 0.f)) return SampledSpectrum(0.f);
        return m_radiance->eval(si, lambda) * m_scale;
    }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u,
                               const SampledWavelengths& lambda) const override {
        EmitterSample es;
        if (!m_shape) return es;  // pdf 0: never attached (preprocess reports it)
        DirectionSample ds = m_shape->sampleDirection(ref, u);
        es.p = ds.p;
        es.n = ds.n;
        es.wi = ds.wi;
        es.dist = ds.dist;
        // The back side emits nothing; a zero pdf tells the caller to skip the sample.
        if (!(ds.pdf > 0.f) || !std::isfinite(ds.pdf) || !(dot(ds.n, -ds.wi) > 0.f)) return es;
        es.pdf = ds.pdf;
        es.L = radianceAt(ds, -ds.wi, lambda);
        return es;
    }

    float pdfDirect(const Point3f& ref, const SurfaceInteraction& si) const override {
        if (!m_shape || !(dot(si.n, si.wo) > 0.f)) return 0.f;
        return m_shape->pdfDirection(ref, si);
    }

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir,
                                  const SampledWavelengths& lambda) const override {
        EmissionSample es;
        if (!m_shape) return es;
        PositionSample ps = m_shape->samplePosition(uPos);
        Vector3f local = m_warp.sample(uDir);
        Frame frame(ps.n);
        Vector3f d = frame.toWorld(local);
        es.ray = Ray{offsetRayOrigin(ps.p, ps.n, d), d, Infinity};
        es.n = ps.n;
        es.pdfPosition = ps.pdf;
        es.pdfDirection = directionPdf(local);
        if (!(es.pdfPosition > 0.f) || !(es.pdfDirection > 0.f)) return es;
        es.L = radianceAt(ps, d, lambda);
        return es;
    }

    /// Positions uniform by area (IShape::samplePosition), directions cosine-weighted
    /// about the front side's normal n (or drawn by the nested warp in the frame of n).
    bool pdfEmission(const Point3f&, const Normal3f& n, const Vector3f& d, float& pdfPosition,
                     float& pdfDirection) const override {
        float area = m_shape ? m_shape->area() : 0.f;
        pdfPosition = area > 0.f ? 1.f / area : 0.f;
        // The default's density as it always was, cos θ/π read off dot(n, d) directly.
        pdfDirection = m_warp.nested() ? directionPdf(Frame(n).toLocal(d)) : std::max(dot(n, d), 0.f) * InvPi;
        return true;
    }

    /// Φ = π · A · L for a Lambertian emitter of constant radiance L (luminance-weighted).
    float power() const override { return m_shape ? Pi * m_shape->area() * m_luminance * m_scale : 0.f; }

private:
    std::string name() const { return typeName().empty() ? std::string("emitter 'area'") : typeName(); }

    /// The warp's density of a direction in the normal's frame; zero at or below the
    /// surface (the back side emits nothing).
    float directionPdf(const Vector3f& local) const { return local.z > 0.f ? m_warp.pdf(local) : 0.f; }

    /// The unscaled radiance as a function of wavelength (constant textures only).
    std::function<float(float)> radiance() const {
        return [t = m_radiance](float l) { return t->eval({}, SampledWavelengths::constant(l))[0]; };
    }

    /// Scaled radiance leaving the sampled point ps toward wo. A constant radiance (nearly
    /// every scene) is read without building the surface point: this runs at every light
    /// sample.
    SampledSpectrum radianceAt(const PositionSample& ps, const Vector3f& wo, const SampledWavelengths& lambda) const {
        static const SurfaceInteraction anywhere;
        if (m_constant) return m_radiance->eval(anywhere, lambda) * m_scale;
        return m_radiance->eval(pointOf(ps, wo), lambda) * m_scale;
    }

    /// The surface point a texture is evaluated at.
    SurfaceInteraction pointOf(const PositionSample& ps, const Vector3f& wo) const {
        SurfaceInteraction si;
        si.shape = m_shape;
        si.p = ps.p;
        si.n = ps.n;
        si.shading = Frame(ps.n);
        si.uv = ps.uv;
        si.wo = wo;
        return si;
    }

    Ref<ITexture> m_radiance;
    const IShape* m_shape = nullptr;
    EmissionScale m_emission;
    float m_scale = 1.f;  // scale · luminance/power normalisation
    float m_luminance = 0.f;
    bool m_constant = false;  // the radiance is the same everywhere
    DirectionWarp m_warp;     // the emission direction sampler
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::AreaEmitter)
