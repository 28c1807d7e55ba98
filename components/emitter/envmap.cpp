// emitter "envmap" — an environment map: radiance from every direction, read from a
// latitude-longitude image.
//
// Convention (Mitsuba 3's, +Y up in the emitter's frame): the texture coordinate
// (u, v) ∈ [0, 1)² means θ = π v from +Y and φ = 2π u, the direction
// (sin φ sin θ, cos θ, −cos φ sin θ): the top row is the zenith, the left and right
// edges look along −Z, a quarter of the width along +X, the middle along +Z. Radiance is interpolated
// bilinearly like Mitsuba's: texel centres in u (wrapping around in φ), the first and
// last rows exactly at the poles in v. Each texel's linear RGB becomes an illuminant
// spectrum (Jakob–Hanika sigmoid scaled to half its peak, times D65); the four corner
// spectra and their scales are interpolated separately, as Mitsuba does.
//
// Direct lighting importance-samples a piecewise-constant density over the cells
// between texel centres, weighted by luminance · ∫ sin θ dθ (pbrt-v4 §12.5.2; Mitsuba
// uses a bilinear hierarchical warp instead: a different but equally unbiased density).
//
// Parameters (Mitsuba 3's `envmap`):
//   filename          string (required)  image file (EXR, HDR, PNG, ...), linear or sRGB
//   scale             float ≥ 0 (default 1)  factor on the radiance
//   to_world          transform  orientation of the map (rotations; scale is ignored)
//   mis_compensation  bool (default false)  subtract the mean from the sampling weights
//                     of direct sampling (Karlík et al. 2019, "MIS Compensation", ACM TOG
//                     38(6)); emission sampling keeps the plain luminance, or light
//                     tracing would miss the darker half of the map's flux
//
// Reference: pbrt-v4 §12.5.2 (image infinite lights); Mitsuba 3 `envmap`.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/math/distribution2d.hpp"
#include "effigi/render/bitmap.hpp"
#include "effigi/render/scene_sphere.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/upsample.hpp"

#include <optional>

namespace effigi {
namespace {

class EnvMapEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "envmap", "Environment map: radiance from a latitude-longitude image (+Y up).");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §12.5.2");
        s.string("filename", "", "Latitude-longitude image (EXR, HDR, PNG, JPEG, ...)").isRequired();
        s.real("scale", 1.0, "Factor on the radiance").atLeast(0.0);
        s.transform("to_world", "Orientation of the map (its +Y is the zenith)");
        s.boolean("mis_compensation", false, "Sample by max(luminance − mean, 0) (MIS compensation)");
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule (noise only)");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp) and
        // tests/test_emitters_extra.cpp, extremes included.
        const std::string sky = "tests/data/emitters/sky.exr";
        s.addConformance({"default", {{"filename", sky}}});
        s.addConformance({"mis compensation", {{"filename", sky}, {"mis_compensation", true}}});
        s.addConformance({"dark", {{"filename", sky}, {"scale", 0.0}}});
        return s;
    }

    explicit EnvMapEmitter(const Properties& p) : m_scale(p.getFloat("scale")) {
        Transform toWorld = p.getTransform("to_world");
        if (!toWorld.isFinite() || glm::determinant(glm::mat3(toWorld.matrix())) == 0.f)
            failAt(p.whereOf("to_world"), "{}: to_world must be finite and invertible", p.describe());
        m_toWorld = toWorld;
        m_toLocal = toWorld.inverse();
        Bitmap image;
        try {
            image = Bitmap::load(p.getPath("filename"));
        } catch (const Error& e) {
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        if (image.empty()) failAt(p.whereOf("filename"), "{}: the image is empty", p.describe());
        image.convertToLinear();
        loadTexels(image);
        // The brightest texel's radiance: its scale times the peak of the normalised D65 (the
        // sigmoid is at most 1), as radiance() evaluates it.
        float d65Peak = 0.f;
        for (int i = 0; i < cie::TableSize; ++i) d65Peak = std::max(d65Peak, cie::D65[i] * m_d65Norm);
        checkEmittedPeak(p, "filename", double(m_maxTexelScale) * double(d65Peak), double(m_scale));
        buildDistribution(p.getBool("mis_compensation"));
    }

    std::uint32_t flags() const override { return EmitterInfinite; }

    void preprocess(const BBox3f& bounds) override { m_sphere = SceneSphere::around(bounds); }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        float pdf;
        Vector3f local;
        if (!sampleLocal(m_distribution, u, local, pdf)) return es;
        es.wi = normalize(m_toWorld.vector(local));
        es.p = m_sphere.beyond(ref, es.wi);
        es.n = -es.wi;
        es.dist = Infinity;
        es.pdf = pdf;
        es.L = radiance(local, lambda);
        return es;
    }

    SampledSpectrum evalEnvironment(const Vector3f& d, const SampledWavelengths& lambda) const override {
        return radiance(toLocal(d), lambda);
    }

    float pdfEnvironment(const Point3f&, const Vector3f& d) const override {
        if (m_distribution.isZero()) return 0.f;
        Vector3f local = toLocal(d);
        float sinTheta = safeSqrt(local.x * local.x + local.z * local.z);
        if (!(sinTheta > 0.f)) return 0.f;
        Point2f uv = directionToUV(local);
        float s = uv.x - 0.5f / float(m_width);
        s -= std::floor(s);
        return m_distribution.pdf(Point2f(std::min(s, OneMinusEpsilon), uv.y)) / (2.f * Pi * Pi * sinTheta);
    }

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir,
                                  const SampledWavelengths& lambda) const override {
        EmissionSample es;
        float pdf;
        Vector3f local;
        // MIS compensation only suits direct lighting, where BSDF sampling covers the
        // directions darker than the mean; emission (light tracing, photons) must reach
        // every direction that emits, so it samples the plain luminance.
        if (!sampleLocal(m_emissionDistribution ? *m_emissionDistribution : m_distribution, uDir, local, pdf))
            return es;
        Vector3f d = -normalize(m_toWorld.vector(local));  // travels from the map into the scene
        es.ray = m_sphere.parallelRay(d, uPos);
        es.n = d;
        es.pdfPosition = 1.f / m_sphere.area();
        es.pdfDirection = pdf;
        es.L = radiance(local, lambda);
        return es;
    }

    /// Flux through the scene's cross-section, π r² · ∫ Y dω (only used to weigh lights).
    float power() const override { return m_sphere.area() * m_radiantLuminance; }

private:
    /// One texel: the sigmoid polynomial of its colour scaled to peak ½, and that scale.
    struct Texel {
        RGBSigmoidPolynomial poly;
        float scale = 0.f;
    };

    void loadTexels(const Bitmap& image) {
        m_width = image.width();
        // One row would put the zenith and nadir on the same texels: repeat it, making
        // the map constant in θ.
        int rows = image.height(), channels = image.channels();
        m_height = std::max(rows, 2);
        const RGBToSpectrumTable& table = RGBToSpectrumTable::sRGB();
        m_texels.resize(std::size_t(m_width) * std::size_t(m_height));
        m_luminance.resize(m_texels.size());
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x) {
                const float* px = image.pixel(x, std::min(y, rows - 1));
                Vector3f rgb = channels >= 3 ? Vector3f(px[0], px[1], px[2]) : Vector3f(px[0]);
                // Bitmap already reads NaN/Inf as 0; negative values emit nothing.
                rgb = glm::max(rgb, Vector3f(0.f));
                Texel& t = m_texels[index(x, y)];
                t.scale = 2.f * maxComponent(rgb);
                m_maxTexelScale = std::max(m_maxTexelScale, t.scale);
                if (t.scale > 0.f) t.poly = table(rgb / t.scale);
                m_luminance[index(x, y)] = dot(rgb, Vector3f(0.2126f, 0.7152f, 0.0722f));
            }
    }

    /// Cell (i, j) spans texel centres i..i+1 (wrapping) and rows j..j+1; its weight is
    /// the mean corner luminance times ∫ sin θ dθ over the cell, so that a cell next to a
    /// pole gets the little solid angle it covers.
    void buildDistribution(bool misCompensation) {
        float offset = 0.f;
        if (misCompensation) {
            double sum = 0.0;
            float lo = Infinity;
            for (float l : m_luminance) sum += l, lo = std::min(lo, l);
            float mean = float(sum / double(m_luminance.size()));
            // A (nearly) constant map would lose every weight: keep the plain density.
            if (mean - lo > 0.01f * mean) offset = mean;
        }
        int cellsV = m_height - 1;
        // With compensation, emission sampling keeps the plain weights beside them.
        std::vector<float> weights(std::size_t(m_width) * std::size_t(cellsV)), plain(offset > 0.f ? weights.size() : 0);
        double integral = 0.0;
        for (int j = 0; j < cellsV; ++j) {
            float bandSolid = std::cos(Pi * float(j) / float(cellsV)) - std::cos(Pi * float(j + 1) / float(cellsV));
            for (int i = 0; i < m_width; ++i) {
                int i1 = (i + 1) % m_width;
                float mean = 0.25f * (m_luminance[index(i, j)] + m_luminance[index(i1, j)] +
                                      m_luminance[index(i, j + 1)] + m_luminance[index(i1, j + 1)]);
                integral += double(mean) * double(bandSolid) * 2.0 * Pi / double(m_width);
                const std::size_t cell = std::size_t(j) * std::size_t(m_width) + std::size_t(i);
                weights[cell] = std::max(mean - offset, 0.f) * std::max(bandSolid, 0.f);
                if (!plain.empty()) plain[cell] = mean * std::max(bandSolid, 0.f);
            }
        }
        m_radiantLuminance = float(integral) * m_scale;
        m_distribution = Distribution2D(weights, m_width, cellsV);
        if (!plain.empty()) m_emissionDistribution = Distribution2D(plain, m_width, cellsV);
        m_luminance.clear();
        m_luminance.shrink_to_fit();
    }

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(m_width) + std::size_t(x); }

    Vector3f toLocal(const Vector3f& d) const { return normalize(m_toLocal.vector(d)); }

    static Point2f directionToUV(const Vector3f& d) {
        float u = std::atan2(d.x, -d.z) * Inv2Pi;
        return Point2f(u - std::floor(u), safeAcos(d.y) * InvPi);
    }

    /// A local direction drawn from `dist` (one of the map's cell distributions) and its
    /// solid-angle density.
    bool sampleLocal(const Distribution2D& dist, const Point2f& u, Vector3f& local, float& pdf) const {
        if (dist.isZero()) return false;
        float pdfUV;
        Point2f sv = dist.sample(u, pdfUV);
        float phi = 2.f * Pi * (sv.x + 0.5f / float(m_width)), theta = Pi * sv.y;
        float sinTheta = std::sin(theta);
        if (!(pdfUV > 0.f) || !(sinTheta > 0.f)) return false;
        local = Vector3f(std::sin(phi) * sinTheta, std::cos(theta), -std::cos(phi) * sinTheta);
        pdf = pdfUV / (2.f * Pi * Pi * sinTheta);
        return true;
    }

    /// Bilinear radiance in the local direction d (unit).
    SampledSpectrum radiance(const Vector3f& d, const SampledWavelengths& lambda) const {
        Point2f uv = directionToUV(d);
        float x = uv.x * float(m_width) - 0.5f, y = std::clamp(uv.y, 0.f, 1.f) * float(m_height - 1);
        float fx = std::floor(x), fy = std::min(std::floor(y), float(m_height - 2));
        float wx = x - fx, wy = y - fy;
        int x0 = (int(fx) % m_width + m_width) % m_width, x1 = (x0 + 1) % m_width;
        int y0 = int(fy), y1 = y0 + 1;
        const Texel* c[4] = {&m_texels[index(x0, y0)], &m_texels[index(x1, y0)], &m_texels[index(x0, y1)],
                             &m_texels[index(x1, y1)]};
        float w[4] = {(1 - wx) * (1 - wy), wx * (1 - wy), (1 - wx) * wy, wx * wy};
        float scale = 0.f;
        for (int k = 0; k < 4; ++k) scale += w[k] * c[k]->scale;
        SampledSpectrum L(0.f);
        if (!(scale > 0.f)) return L;
        for (int i = 0; i < NSpectrumSamples; ++i) {
            float s = 0.f;
            for (int k = 0; k < 4; ++k)
                if (w[k] > 0.f && c[k]->scale > 0.f) s += w[k] * c[k]->poly(lambda[i]);
            L[i] = s * scale * m_scale * lambda.d65(i) * m_d65Norm;
        }
        return L;
    }

    std::vector<Texel> m_texels;
    std::vector<float> m_luminance;  // per texel, only while building the distribution
    int m_width = 0, m_height = 0;
    float m_scale = 1.f, m_radiantLuminance = 0.f;
    float m_d65Norm = cie::d65Normalization();
    float m_maxTexelScale = 0.f;  // the brightest texel's scale (load check)
    Transform m_toWorld, m_toLocal;
    Distribution2D m_distribution;                        // direct sampling (maybe compensated)
    std::optional<Distribution2D> m_emissionDistribution;  // emission, when compensated
    SceneSphere m_sphere;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::EnvMapEmitter)
