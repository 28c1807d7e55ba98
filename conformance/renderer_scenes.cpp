// Scenes of the renderer suite with exact pixel values (see renderer_scenes.hpp):
//  - furnace sphere: a white (ρ = 1) diffuse sphere under a constant environment. A convex
//    surface never sees itself, so one bounce of the environment is all its light: every
//    pixel is ρ·L for max_depth ≥ 2, and 0 at max_depth 1 (only the sphere is seen).
//  - sky plane: the top of a diffuse plane of ρ = 0.5 under a constant sky: ρ·L likewise.
//  - white furnace box: a box of white two-sided diffuse walls, open at the top, in a
//    constant environment, seen through the opening. Lossless surfaces in a uniform
//    radiance field leave it uniform (L is a solution of the rendering equation when every
//    albedo is 1), so every pixel is L — for unbounded depth only; at a finite depth the
//    light lost depends on the geometry.
//  - enclosure ρ: the inside of a closed cube whose walls all emit Le and reflect ρ. Light
//    arriving at any point is the same from every direction, so a path of k bounces
//    carries ρᵏ Le: L = Le Σ_{k<d} ρᵏ at max_depth d (from k = 1 when emitters seen
//    directly are hidden), Le/(1 − ρ) unbounded; ρ = 0.5, 0.9, 0.99 (stiff).
// The cameras frame every scene so that each pixel sees the same surface (the sphere's
// silhouette, the plane, the box's inside, one wall of the cube) and nothing else.
#include "conformance/renderer_scenes.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace effigi::conform {

namespace {

// A flat emission spectrum (a <float> emission would be D65, as in Mitsuba): radiosity's
// spectral bins then hold it exactly.
const char* const Sky = R"(<emitter type="constant"><spectrum name="radiance" value="1"/></emitter>)";

std::string diffuse(double rho) {
    return fmt::format(R"(<bsdf type="diffuse"><float name="reflectance" value="{}"/></bsdf>)", rho);
}

/// A rectangle ([-1,1]², normal +z) placed by `place` (XML transform steps), with `bsdf`.
std::string rectangle(const std::string& place, const std::string& bsdf) {
    return fmt::format(R"(<shape type="rectangle"><transform name="to_world">{}</transform>{}</shape>)", place, bsdf);
}

/// Σ_{k=k0}^{d−1} ρᵏ, d = −1 unbounded.
double series(double rho, int k0, int depth) {
    if (depth < 0) return std::pow(rho, k0) / (1.0 - rho);
    double sum = 0.0;
    for (int k = k0; k < depth; ++k) sum += std::pow(rho, k);
    return sum;
}

/// One bounce of the light: ρ from max_depth 2 on (or unbounded), nothing below.
std::function<std::optional<double>(const Semantics&)> oneBounce(double rho) {
    return [rho](const Semantics& s) -> std::optional<double> { return s.depth >= 0 && s.depth < 2 ? 0.0 : rho; };
}

} // namespace

std::vector<AnalyticScene> analyticScenes(bool quick) {
    std::vector<AnalyticScene> out;
    auto add = [&](std::string name, bool env, std::string body, std::string origin, std::string target, double fov,
                   std::function<std::optional<double>(const Semantics&)> exact) -> AnalyticScene& {
        AnalyticScene s;
        s.name = std::move(name), s.environment = env, s.body = std::move(body);
        s.origin = std::move(origin), s.target = std::move(target), s.fov = fov, s.exact = std::move(exact);
        return out.emplace_back(std::move(s));
    };
    add("furnace sphere", true, std::string(R"(<shape type="sphere">)") + diffuse(1.0) + "</shape>" + Sky, "0, 0, 4",
        "0, 0, 0", 14.0, oneBounce(1.0));
    add("sky plane", true, rectangle(R"(<scale value="10"/>)", diffuse(0.5)) + Sky, "0, 0, 2", "0, 0, 0", 60.0,
        oneBounce(0.5));
    {
        // Floor z = 0, walls x = ±1 and y = ±1 up to z = 2, open at z = 2.
        const std::string white = R"(<bsdf type="twosided">)" + diffuse(1.0) + "</bsdf>";
        std::string body = rectangle("", white);
        for (int sign : {-1, 1}) {
            body += rectangle(fmt::format(R"(<rotate y="1" angle="90"/><translate value="{}, 0, 1"/>)", sign), white);
            body += rectangle(fmt::format(R"(<rotate x="1" angle="90"/><translate value="0, {}, 1"/>)", sign), white);
        }
        add("white furnace box", true, body + Sky, "0, 0, 4", "0, 0, 0", 15.0,
            [](const Semantics& m) -> std::optional<double> {
                if (m.depth < 0) return 1.0;
                if (m.depth < 2) return 0.0;
                return std::nullopt;
            })
            .why = "radiance at a finite max_depth depends on the box's geometry (no closed form)";
    }
    for (double rho : {0.5, 0.9, 0.99}) {
        if (quick && rho == 0.9) continue;
        std::string body = fmt::format(R"(<shape type="cube"><boolean name="flip_normals" value="true"/>{})"
                                       R"(<emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>)",
                                       diffuse(rho));
        AnalyticScene& s = add(fmt::format("enclosure ρ = {}", rho), false, body, "0, 0, 0", "0, 0, 1", 60.0,
                               [rho](const Semantics& m) -> std::optional<double> {
                                   return series(rho, m.hideEmitters ? 1 : 0, m.depth);
                               });
        s.seenArea = 1.0 / 6.0;  // one face of the cube
        if (rho > 0.975) {
            s.stochasticDepth = 16;
            s.stochasticWhy = "Russian roulette as Mitsuba's (survival ≤ 0.95) lets path weights grow like "
                              "(ρ/0.95)ᵏ: for ρ > √0.95 the estimator's variance is infinite and no test of its mean "
                              "is valid; tested up to max_depth 16 (and by radiosity)";
        }
    }
    return out;
}

std::unique_ptr<Scene> loadAnalytic(const AnalyticScene& s, int res, int spp) {
    std::string text = fmt::format(
        R"(<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="{}"/>)"
        R"(<float name="near_clip" value="{}"/>)"
        R"(<transform name="to_world"><lookat origin="{}" target="{}" up="0, 1, 0"/></transform>)"
        R"(<sampler type="independent"><integer name="sample_count" value="{}"/></sampler>)"
        R"(<film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>)"
        R"(<rfilter type="box"/></film></sensor>{}</scene>)",
        s.fov, NearClip, s.origin, s.target, spp, res, res, s.body);
    return loadScene(*xml::parseString(text, "renderer suite: " + s.name));
}

double emittedGrey(const Scene& scene) {
    // Emitted radiance toward the camera: the environment's, or that of the surface the
    // film's centre sees.
    const IEmitter* env = scene.environments().empty() ? nullptr : scene.environments()[0];
    SurfaceInteraction si;
    if (!env) {
        CameraSample cs;
        cs.pFilm = Point2f(Vector2f(scene.camera().film().fullSize()) * 0.5f);
        SampledSpectrum w;
        Ray ray = scene.camera().generateRay(cs, SampledWavelengths::sampleVisible(0.5f), w);
        if (!scene.intersect(ray, si) || !si.emitter) return 0.0;
    }
    constexpr int N = 1 << 14;
    glm::dvec3 xyz(0.0);
    for (int i = 0; i < N; ++i) {
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(float((i + 0.5) / N));
        SampledSpectrum L = env ? env->evalEnvironment(Vector3f(0.f, 0.f, 1.f), lambda) : si.emitter->eval(si, lambda);
        xyz += glm::dvec3(cie::toXYZ(L, lambda));
    }
    Vector3f rgb = xyzToLinearSRGB(Vector3f(xyz / double(N)));
    return (double(rgb.x) + rgb.y + rgb.z) / 3.0;
}

std::vector<double> greyPixels(const Image& image) {
    const auto& names = image.channelNames;
    int c[3];
    for (int k = 0; k < 3; ++k) {
        auto it = std::find(names.begin(), names.end(), std::string(1, "RGB"[k]));
        if (it == names.end()) return {};
        c[k] = int(it - names.begin());
    }
    std::vector<double> out;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            out.push_back((double(image.at(x, y, c[0])) + image.at(x, y, c[1]) + image.at(x, y, c[2])) / 3.0);
    return out;
}

} // namespace effigi::conform
