// renderer "aov" — arbitrary output variables: what the camera sees first, per pixel.
//
// Parameter `aovs`: a comma-separated list of "name:type" (Mitsuba 3's syntax), types
// albedo (BSDF albedo as linear sRGB), sh_normal, geo_normal (world, unit), depth
// (distance along the camera ray), position, uv. Each becomes channels "name.R/G/B",
// "name.X/Y/Z", "name.U/V" or "name.Z" of the output EXR; pixels that see nothing are 0.
// Used for denoiser inputs and to debug scenes (normals facing the wrong way, etc).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <sstream>

namespace effigi {
namespace {

enum class AovType { Albedo, ShNormal, GeoNormal, Depth, Position, UV };

struct Aov {
    AovType type;
    int offset;  // first channel
};

class AovRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "aov", "Arbitrary output variables (albedo, normals, depth, ...) of the first hit.");
        s.string("aovs", "albedo:albedo, nn:sh_normal, dd:depth",
                 "Comma-separated name:type list; types albedo, sh_normal, geo_normal, depth, position, uv");
        return s;
    }

    explicit AovRenderer(const Properties& p) {
        static const std::vector<std::pair<std::string, AovType>> types = {
            {"albedo", AovType::Albedo},  {"sh_normal", AovType::ShNormal}, {"geo_normal", AovType::GeoNormal},
            {"depth", AovType::Depth},    {"position", AovType::Position},  {"uv", AovType::UV}};
        std::stringstream ss(p.getString("aovs"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            item.erase(0, item.find_first_not_of(" \t\n"));
            item.erase(item.find_last_not_of(" \t\n") + 1);
            if (item.empty()) continue;
            auto colon = item.find(':');
            if (colon == std::string::npos || colon == 0)
                failAt(p.whereOf("aovs"), "renderer 'aov': entry '{}' of 'aovs' must be name:type", item);
            std::string name = item.substr(0, colon), type = item.substr(colon + 1);
            auto it = std::find_if(types.begin(), types.end(), [&](auto& t) { return t.first == type; });
            if (it == types.end()) {
                std::vector<std::string> names;
                for (auto& t : types) names.push_back(t.first);
                std::string hint = didYouMean(type, names);
                failAt(p.whereOf("aovs"), "renderer 'aov': unknown AOV type '{}'{} (types: {})", type,
                       hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), fmt::join(names, ", "));
            }
            static const char* rgb[] = {"R", "G", "B"};
            static const char* xyz[] = {"X", "Y", "Z"};
            static const char* uv[] = {"U", "V"};
            m_aovs.push_back({it->second, int(m_channels.size())});
            switch (it->second) {
            case AovType::Albedo: for (auto c : rgb) m_channels.push_back(name + "." + c); break;
            case AovType::Depth: m_channels.push_back(name + ".Z"); break;
            case AovType::UV: for (auto c : uv) m_channels.push_back(name + "." + c); break;
            default: for (auto c : xyz) m_channels.push_back(name + "." + c); break;
            }
        }
        if (m_aovs.empty()) failAt(p.whereOf("aovs"), "renderer 'aov': 'aovs' lists no outputs");
        if (m_channels.size() > MaxChannels)
            failAt(p.whereOf("aovs"), "renderer 'aov': at most {} channels", MaxChannels);
        // Albedo is shown as the colour it has under the sRGB white (normalised D65).
        m_white = Spectrum::fromRGB(Vector3f(1.f), SpectrumKind::Illuminant);
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        const ICamera& camera = scene.camera();
        Point2f offset(camera.film().cropOffset());
        return renderTiles(scene, control, m_channels, "AOVs",
                           [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block,
                               TileStats& stats) {
                               sampler.startPixel(px);
                               for (std::uint64_t i = range.first; i < range.first + range.count; ++i) {
                                   sampler.startSample(i);
                                   samplePixel(scene, px, offset, sampler, block);
                                   ++stats.samples;
                               }
                           });
    }

private:
    static constexpr std::size_t MaxChannels = 32;

    void samplePixel(const Scene& scene, Point2i px, Point2f offset, ISampler& sampler, ImageBlock& block) const {
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(sampler.get1D());
        Point2f pFilm = Point2f(px) + sampler.getPixel2D();
        SampledSpectrum weight(1.f);
        Ray ray = scene.camera().generateRay({pFilm + offset, sampler.get2D(), 0.f}, lambda, weight);
        float values[MaxChannels] = {};
        SurfaceInteraction si;
        if (scene.intersect(ray, si)) {
            for (const Aov& a : m_aovs) {
                float* v = values + a.offset;
                switch (a.type) {
                case AovType::Albedo: {
                    if (!si.bsdf) break;
                    SampledSpectrum rho = si.bsdf->albedo(si, lambda) * m_white.sample(lambda);
                    Vector3f rgb = xyzToLinearSRGB(cie::toXYZ(rho, lambda));
                    v[0] = rgb.x, v[1] = rgb.y, v[2] = rgb.z;
                    break;
                }
                case AovType::ShNormal: v[0] = si.shading.n.x, v[1] = si.shading.n.y, v[2] = si.shading.n.z; break;
                case AovType::GeoNormal: v[0] = si.n.x, v[1] = si.n.y, v[2] = si.n.z; break;
                case AovType::Depth: v[0] = si.t * length(ray.d); break;
                case AovType::Position: v[0] = si.p.x, v[1] = si.p.y, v[2] = si.p.z; break;
                case AovType::UV: v[0] = si.uv.x, v[1] = si.uv.y; break;
                }
            }
        }
        block.put(pFilm, values);
    }

    std::vector<Aov> m_aovs;
    std::vector<std::string> m_channels;
    Spectrum m_white;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::AovRenderer)
