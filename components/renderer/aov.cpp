// renderer "aov" — arbitrary output variables: what the camera sees first, per pixel,
// optionally next to the images of nested renderers (Mitsuba 3's `aov`).
//
// Parameter `aovs`: a comma-separated list of "name:type" (Mitsuba 3's syntax and
// channel names): albedo (BSDF albedo as linear sRGB: name.R/G/B), depth (distance along
// the camera ray: name.T), position, geo_normal, sh_normal, dp_du, dp_dv (world:
// name.X/Y/Z), uv (name.U/V), prim_index, shape_index (name.I: the primitive in its
// shape; 1 + the index of the scene shape hit, its instance for an instanced member, as
// Mitsuba). effigi adds, asked of the shape only when listed (IShape::localGeometry):
// curvature (mean curvature, name.H), gaussian_curvature (name.K; signs as
// effigi::curvature: a sphere with outward normals has H = 1/r, K = 1/r²) and
// object_position (the point before to_world, name.X/Y/Z). Pixels that see nothing are 0.
// Nested renderers (nested <integrator> in Mitsuba; they must render single samples, see
// ISampleRenderer): the first one's radiance is the colour image; each one `name` also
// gets channels name.R/G/B (linear sRGB of its samples), name.A (1 where the camera ray
// finds a surface or an environment) and name.<its own channels>, before the AOVs. A
// child without a name attribute is called "_arg_<i>". Without nested renderers the
// colour image is black, as in Mitsuba. Used for denoiser inputs and to debug scenes.
// Reference: Mitsuba 3, src/integrators/aov.cpp (names, layout).
#include "nested_renderer.hpp"
#include "sampled_renderer.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <span>
#include <sstream>

namespace effigi {
namespace {

enum class AovType {
    Albedo, ShNormal, GeoNormal, Depth, Position, UV, DpDu, DpDv, PrimIndex, ShapeIndex,
    MeanCurvature, GaussianCurvature, ObjectPosition
};

struct AovKind {
    const char* name;
    AovType type;
    std::vector<const char*> suffixes;  // channel name suffixes, Mitsuba's
};

const std::vector<AovKind>& aovKinds() {
    static const std::vector<AovKind> kinds = {
        {"albedo", AovType::Albedo, {"R", "G", "B"}},
        {"depth", AovType::Depth, {"T"}},
        {"position", AovType::Position, {"X", "Y", "Z"}},
        {"uv", AovType::UV, {"U", "V"}},
        {"geo_normal", AovType::GeoNormal, {"X", "Y", "Z"}},
        {"sh_normal", AovType::ShNormal, {"X", "Y", "Z"}},
        {"dp_du", AovType::DpDu, {"X", "Y", "Z"}},
        {"dp_dv", AovType::DpDv, {"X", "Y", "Z"}},
        {"prim_index", AovType::PrimIndex, {"I"}},
        {"shape_index", AovType::ShapeIndex, {"I"}},
        {"curvature", AovType::MeanCurvature, {"H"}},
        {"gaussian_curvature", AovType::GaussianCurvature, {"K"}},
        {"object_position", AovType::ObjectPosition, {"X", "Y", "Z"}}};
    return kinds;
}

class AovRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "aov", "Arbitrary output variables (albedo, normals, depth, ...) of the first hit.");
        s.string("aovs", "albedo:albedo, nn:sh_normal, dd:depth",
                 "Comma-separated name:type list (Mitsuba requires it; effigi defaults to this); types "
                 "albedo, depth, position, uv, geo_normal, sh_normal, dp_du, dp_dv, prim_index, shape_index, "
                 "curvature, gaussian_curvature, object_position");
        s.children("renderer", "Renderers whose images come first (nested <integrator> in Mitsuba)");
        addIntegratorParam(s);
        s.addConformance({"default", {}});
        s.addConformance({"every AOV type", {{"aovs", std::string("a:albedo, d:depth, p:position, uv:uv, g:geo_normal, "
                                                                  "n:sh_normal, u:dp_du, v:dp_dv, i:prim_index, "
                                                                  "s:shape_index, h:curvature, k:gaussian_curvature, "
                                                                  "o:object_position")}}});
        if (auto path = nestedRenderer("path")) s.addConformance({"nested path", {{"path", *path}}});
        return s;
    }

    explicit AovRenderer(const Properties& p) : SampledRenderer(p) {
        for (NestedRenderer& n : nestedRenderers(p)) {
            std::vector<std::string> own = n.renderer->sampleChannels();
            for (const char* c : {".R", ".G", ".B", ".A"}) m_channels.push_back(n.name + c);
            for (const std::string& c : own) m_channels.push_back(n.name + "." + c);
            m_nested.push_back({n.renderer, own.size()});
            if (const IRenderer* r = query<IRenderer>(n.renderer.get())) {
                m_media = std::min(m_media, r->mediaSupport());
                m_motion = m_motion && r->rendersMotion();
            }
        }
        parseAovs(p);
        if (m_aovs.empty() && m_nested.empty())
            failAt(p.whereOf("aovs"), "renderer 'aov': 'aovs' lists no outputs and no renderer is nested");
        if (m_channels.size() > 256) failAt(p.whereOf("aovs"), "renderer 'aov': more than 256 channels");
        // Albedo is shown as the colour it has under the sRGB white (normalised D65).
        m_white = Spectrum::fromRGB(Vector3f(1.f), SpectrumKind::Illuminant);
    }

    std::vector<std::string> sampleChannels() const override { return m_channels; }
    /// What the weakest of the nested renderers does with media.
    MediaSupport mediaSupport() const override { return m_media; }
    /// Motion blur if every nested renderer renders it (the AOVs come from timed camera rays).
    bool rendersMotion() const override { return m_motion; }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float* channels) const override {
        SurfaceInteraction si;
        Hit h;  // kept for shape_index: the scene shape hit
        if (m_shapeIndex) {
            scene.intersect(std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1));
            if (h.valid()) si = scene.interaction(ray, h);
        }
        const bool hit = m_shapeIndex ? h.valid() : scene.intersect(ray, si);
        float* out = channels;
        SampledSpectrum first(0.f);
        SampledWavelengths firstLambda = lambda;
        for (std::size_t i = 0; i < m_nested.size(); ++i) {
            SampledWavelengths l = lambda;  // each nested renderer sees the wavelengths as drawn
            SampledSpectrum L = m_nested[i].renderer->sampleRadiance(scene, ray, l, sampler, out + 4);
            Vector3f rgb = xyzToLinearSRGB(cie::toXYZ(L, l));
            out[0] = rgb.x, out[1] = rgb.y, out[2] = rgb.z;
            out[3] = hit || !scene.environments().empty() ? 1.f : 0.f;
            out += 4 + m_nested[i].channels;
            if (i == 0) first = L, firstLambda = l;
        }
        lambda = firstLambda;
        if (hit)
            for (const Aov& a : m_aovs) writeAov(a, si, h, ray, lambda, out + a.offset);
        return first;
    }

private:
    struct Aov {
        AovType type;
        int offset;  // first channel, counted from the first AOV channel
    };
    struct Nested {
        Ref<ISampleRenderer> renderer;
        std::size_t channels;
    };

    void parseAovs(const Properties& p) {
        const std::size_t first = m_channels.size();
        std::stringstream ss(p.getString("aovs"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            item.erase(0, item.find_first_not_of(" \t\n"));
            item.erase(item.find_last_not_of(" \t\n") + 1);
            if (item.empty()) continue;
            auto colon = item.find(':');
            if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())
                failAt(p.whereOf("aovs"), "renderer 'aov': entry '{}' of 'aovs' must be name:type", excerpt(item));
            std::string name = item.substr(0, colon), type = item.substr(colon + 1);
            const auto& kinds = aovKinds();
            auto it = std::find_if(kinds.begin(), kinds.end(), [&](const AovKind& k) { return type == k.name; });
            if (it == kinds.end()) {
                std::vector<std::string> names;
                for (const AovKind& k : kinds) names.push_back(k.name);
                std::string hint = didYouMean(type, names);
                failAt(p.whereOf("aovs"), "renderer 'aov': unknown AOV type '{}'{} (types: {})", excerpt(type),
                       hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), fmt::join(names, ", "));
            }
            m_aovs.push_back({it->type, int(m_channels.size() - first)});
            m_shapeIndex = m_shapeIndex || it->type == AovType::ShapeIndex;
            for (const char* c : it->suffixes) m_channels.push_back(name + "." + c);
        }
    }

    void writeAov(const Aov& a, const SurfaceInteraction& si, const Hit& hit, const Ray& ray,
                  const SampledWavelengths& lambda, float* v) const {
        auto put3 = [v](const Vector3f& x) { v[0] = x.x, v[1] = x.y, v[2] = x.z; };
        switch (a.type) {
        case AovType::Albedo:
            if (si.bsdf)
                put3(xyzToLinearSRGB(cie::toXYZ(si.bsdf->albedo(si, lambda) * m_white.sample(lambda), lambda)));
            break;
        case AovType::ShNormal: put3(Vector3f(si.shading.n)); break;
        case AovType::GeoNormal: put3(Vector3f(si.n)); break;
        case AovType::Depth: v[0] = si.t * length(ray.d); break;
        case AovType::Position: put3(Vector3f(si.p)); break;
        case AovType::UV: v[0] = si.uv.x, v[1] = si.uv.y; break;
        case AovType::DpDu: put3(si.dpdu); break;
        case AovType::DpDv: put3(si.dpdv); break;
        case AovType::PrimIndex: v[0] = float(si.prim); break;
        case AovType::ShapeIndex: v[0] = float(hit.shape) + 1.f; break;
        case AovType::MeanCurvature: v[0] = curvature(si, localGeometry(si)).mean; break;
        case AovType::GaussianCurvature: v[0] = curvature(si, localGeometry(si)).gaussian; break;
        case AovType::ObjectPosition: put3(Vector3f(localGeometry(si).objectP)); break;
        }
    }

    std::vector<Nested> m_nested;
    MediaSupport m_media = MediaSupport::Ignores;
    bool m_motion = true;
    std::vector<Aov> m_aovs;
    bool m_shapeIndex = false;  // a shape_index AOV is listed
    std::vector<std::string> m_channels;  // nested renderers' first, then the AOVs
    Spectrum m_white;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::AovRenderer)
