// renderer "moment" — first and second moments of the samples of nested renderers.
//
// Wraps one or more renderers (nested <integrator>/<renderer> elements, Mitsuba 3's
// `moment`). Every camera sample is handed to each nested renderer in turn (through
// ISampleRenderer, effigi/render/tile_renderer.hpp); the film gets, for nested renderer
// `name`, its sample's CIE XYZ in channels "name.X", "name.Y", "name.Z" (after the
// nested renderer's own channels "name.<channel>") and, for each of those channels c,
// the square of the sample value in "m2_c". The filter-weighted film average of the
// squares is the second moment, so Var ≈ m2 − m1² per pixel (times the filter's variance
// factor over the sample count for the pixel mean's variance). The colour image is the
// first nested renderer's. A child declared without a name is called "_arg_<i>" (its
// index among the unnamed ones), as Mitsuba names it.
// Parameters: the nested renderers (at least one); integrator (numerical integrator of
// each pixel, default mean; nested renderers' own integrators are not used).
// Reference: Mitsuba 3, src/integrators/moment.cpp (channel layout and names).
#include "nested_renderer.hpp"
#include "sampled_renderer.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

namespace effigi {
namespace {

class MomentRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "moment", "First and second moments of nested renderers' samples as channels.");
        s.cite("Mitsuba 3, moment integrator");
        s.children("renderer", "Renderers whose samples are recorded (at least one; nested <integrator> in Mitsuba)");
        addIntegratorParam(s);
        // Nested renderers are required: without one there is nothing to instantiate.
        if (auto path = nestedRenderer("path")) s.addConformance({"nested path", {{"path", *path}}});
        if (auto direct = nestedRenderer("direct"), path = nestedRenderer("path"); direct && path)
            s.addConformance({"nested direct, path", {{"direct", *direct}, {"path", *path}}});
        return s;
    }

    explicit MomentRenderer(const Properties& p) : SampledRenderer(p) {
        for (NestedRenderer& n : nestedRenderers(p)) {
            std::vector<std::string> own = n.renderer->sampleChannels();
            for (const std::string& c : own) m_channels.push_back(n.name + "." + c);
            for (const char* c : {".X", ".Y", ".Z"}) m_channels.push_back(n.name + c);
            m_nested.push_back({n.renderer, own.size()});
            if (const IRenderer* r = query<IRenderer>(n.renderer.get())) {
                m_media = std::min(m_media, r->mediaSupport());
                m_motion = m_motion && r->rendersMotion();
            }
        }
        if (m_nested.empty()) failAt(p.where(), "renderer 'moment': needs at least one nested renderer");
        const std::size_t first = m_channels.size();
        for (std::size_t i = 0; i < first; ++i) m_channels.push_back("m2_" + m_channels[i]);
    }

    std::vector<std::string> sampleChannels() const override { return m_channels; }
    /// What the weakest of the nested renderers does with media.
    MediaSupport mediaSupport() const override { return m_media; }
    /// Motion blur if every nested renderer renders it (the AOVs come from timed camera rays).
    bool rendersMotion() const override { return m_motion; }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float* channels) const override {
        const std::size_t half = m_channels.size() / 2;
        float* out = channels;
        SampledSpectrum first(0.f);
        SampledWavelengths firstLambda = lambda;
        for (std::size_t i = 0; i < m_nested.size(); ++i) {
            // Each nested renderer sees the sample's wavelengths as drawn (one may end
            // the secondary ones, e.g. at a dispersive refraction).
            SampledWavelengths l = lambda;
            SampledSpectrum L = m_nested[i].renderer->sampleRadiance(scene, ray, l, sampler, out);
            out += m_nested[i].channels;
            Vector3f xyz = cie::toXYZ(L, l);
            *out++ = xyz.x, *out++ = xyz.y, *out++ = xyz.z;
            if (i == 0) first = L, firstLambda = l;
        }
        for (std::size_t c = 0; c < half; ++c) channels[half + c] = channels[c] * channels[c];
        lambda = firstLambda;
        return first;
    }

private:
    struct Nested {
        Ref<ISampleRenderer> renderer;
        std::size_t channels;
    };

    std::vector<Nested> m_nested;
    MediaSupport m_media = MediaSupport::Renders;
    bool m_motion = true;
    std::vector<std::string> m_channels;  // first moments, then "m2_" + each
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MomentRenderer)
