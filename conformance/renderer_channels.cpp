// The renderer suite's checks of the channels a renderer writes besides colour, on the sky
// plane of renderer_scenes.cpp (the plane z = 0, normal +z, diffuse ρ = 0.5, seen from 2
// above, straight down, with a 60° field of view), rendered once. All deterministic:
//  - black colour image: a wrapper without nested renderers (aov with AOVs only) renders
//    no colour, as in Mitsuba: every R, G, B is 0;
//  - nested colour: a wrapper's channels of its first nested renderer (aov: name.R/G/B,
//    linear sRGB; moment: name.X/Y/Z) hold what its colour image shows, pixel by pixel
//    (to 1e-4 of the image's largest value: float sums of the same samples);
//  - moments: every channel c with a second moment "m2_c" has m2_c ≥ c² in every pixel
//    (Jensen: the film averages the squares of the samples it averages);
//  - AOVs (the `aovs` parameter, Mitsuba's name:type list) whose value on the plane is
//    known: albedo ρ (grey within 2 %: the sRGB white's spectral round trip and 4
//    wavelengths a sample leave ~0.5 %), sh_normal and geo_normal (0, 0, 1), position on
//    z = 0, depth (from the near plane) between its values at the film's centre and corners.
#include "conformance/renderer_channels.hpp"
#include "conformance/renderer_scenes.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <fmt/format.h>

#include <cmath>
#include <sstream>

namespace effigi::conform {

namespace {

constexpr double PlaneRho = 0.5, Height = 2.0, Tol = 1e-4;
/// Depth is measured from the ray's origin on the near plane: (Height − NearClip) / cos θ,
/// at most at the film's corners, where tan θ = tan 30° · √2.
const double CentreDepth = Height - NearClip, CornerDepth = CentreDepth * std::sqrt(1.0 + 2.0 / 3.0);

int channel(const Image& img, const std::string& name) {
    auto it = std::find(img.channelNames.begin(), img.channelNames.end(), name);
    return it == img.channelNames.end() ? -1 : int(it - img.channelNames.begin());
}

/// The worst pixel of a per-pixel condition, and the first offender.
struct Worst {
    std::uint64_t bad = 0, checked = 0;
    std::string first;
    void note(bool ok, const std::string& what) {
        ++checked;
        if (!ok && bad++ == 0) first = what;
    }
    void report(Target& t, const std::string& check, const std::string& what) const {
        t.expect(check, bad == 0, fmt::format("{} bad of {}", bad, checked), bad ? "first: " + first : what);
    }
};

/// Every pixel's channels `names` against `expect(pixel values) → ok`.
template <typename F> Worst perPixel(const Image& img, const std::vector<int>& c, F&& ok) {
    Worst w;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            std::vector<double> v;
            for (int k : c) v.push_back(img.at(x, y, k));
            std::string at = fmt::format("pixel ({}, {}):", x, y);
            for (double d : v) at += fmt::format(" {:.7g}", d);
            w.note(ok(v), at);
        }
    return w;
}

void checkAovs(Target& t, const Image& img, const std::string& aovs) {
    std::stringstream ss(aovs);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(0, item.find_first_not_of(" \t\n"));
        item.erase(item.find_last_not_of(" \t\n") + 1);
        auto colon = item.find(':');
        if (colon == std::string::npos) continue;
        std::string name = item.substr(0, colon), type = item.substr(colon + 1);
        auto ch = [&](std::initializer_list<const char*> sfx) {
            std::vector<int> c;
            for (const char* s : sfx) c.push_back(channel(img, name + "." + s));
            return c;
        };
        std::vector<int> c;
        std::string check = "aov " + name + ":" + type;
        if (type == "albedo" && (c = ch({"R", "G", "B"}), c[0] >= 0 && c[1] >= 0 && c[2] >= 0)) {
            double sum = 0.0;
            perPixel(img, c, [&](const std::vector<double>& v) { return sum += (v[0] + v[1] + v[2]) / 3.0, true; });
            double mean = sum / (double(img.width) * img.height);
            t.expect(check, std::abs(mean / PlaneRho - 1.0) <= 0.02, fmt::format("mean {:.4f}", mean),
                     fmt::format("grey albedo of the plane: {} within 2 %", PlaneRho));
        } else if ((type == "sh_normal" || type == "geo_normal") && (c = ch({"X", "Y", "Z"}), c[0] >= 0)) {
            perPixel(img, c, [](const std::vector<double>& v) {
                return std::abs(v[0]) <= Tol && std::abs(v[1]) <= Tol && std::abs(v[2] - 1.0) <= Tol;
            }).report(t, check, "(0, 0, 1) ± 1e-4 in every pixel");
        } else if (type == "position" && (c = ch({"X", "Y", "Z"}), c[2] >= 0)) {
            perPixel(img, c, [](const std::vector<double>& v) { return std::abs(v[2]) <= Tol; })
                .report(t, check, "z = 0 ± 1e-4 in every pixel");
        } else if (type == "depth" && (c = ch({"T"}), c[0] >= 0)) {
            perPixel(img, c, [](const std::vector<double>& v) {
                return v[0] >= CentreDepth * (1 - Tol) && v[0] <= CornerDepth * (1 + Tol);
            }).report(t, check, fmt::format("in [{}, {:.4f}] in every pixel", CentreDepth, CornerDepth));
        } else {
            t.skip(check, "no known value on the test plane");
        }
    }
}

} // namespace

void checkChannels(Target& t, bool colour) {
    std::vector<AnalyticScene> scenes = analyticScenes(true);
    auto plane = std::find_if(scenes.begin(), scenes.end(), [](const AnalyticScene& s) { return s.name == "sky plane"; });
    if (plane == scenes.end()) return;
    std::unique_ptr<Scene> scene = loadAnalytic(*plane, 8, 16);
    Ref<IRenderer> r = query<IRenderer>(t.create());
    RenderControl control;
    control.progress = false;
    control.seed = t.derivedSeed("channels");
    r->render(*scene, control);
    const Image img = scene->camera().film().develop();
    const std::vector<int> rgb = {channel(img, "R"), channel(img, "G"), channel(img, "B")};
    if (img.channels() <= 3 || rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) return;  // colour only
    const auto& names = img.channelNames;
    if (!colour)
        perPixel(img, rgb, [](const std::vector<double>& v) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; })
            .report(t, "black colour image", "R = G = B = 0 without nested renderers (Mitsuba)");

    // The first nested renderer's name: its entry's, or Mitsuba's "_arg_0".
    for (const auto& [key, value] : t.configuration().params) {
        const auto* c = std::get_if<ComponentValue>(&value);
        if (!c || c->tag != "renderer") continue;
        const std::string name = key.empty() ? "_arg_0" : key;
        std::vector<int> own = {channel(img, name + ".R"), channel(img, name + ".G"), channel(img, name + ".B")};
        const bool xyz = own[0] < 0;
        if (xyz) own = {channel(img, name + ".X"), channel(img, name + ".Y"), channel(img, name + ".Z")};
        if (own[0] < 0 || own[1] < 0 || own[2] < 0) break;
        double peak = 0.0;
        for (float v : img.pixels) peak = std::max(peak, double(std::abs(v)));
        std::vector<int> both = rgb;
        both.insert(both.end(), own.begin(), own.end());
        perPixel(img, both, [&](const std::vector<double>& v) {
            Vector3f o{float(v[3]), float(v[4]), float(v[5])};
            if (xyz) o = xyzToLinearSRGB(o);
            return std::abs(v[0] - o.x) <= 1e-4 * peak && std::abs(v[1] - o.y) <= 1e-4 * peak &&
                   std::abs(v[2] - o.z) <= 1e-4 * peak;
        }).report(t, "nested colour", fmt::format("{}.{} equal the colour image to 1e-4 of its peak", name,
                                                  xyz ? "X/Y/Z" : "R/G/B"));
        break;
    }
    Worst moments;
    for (std::size_t c = 0; c < names.size(); ++c) {
        int m2 = channel(img, "m2_" + names[c]);
        if (m2 < 0) continue;
        Worst w = perPixel(img, {int(c), m2}, [](const std::vector<double>& v) {
            return v[1] >= v[0] * v[0] * (1.0 - Tol) - 1e-12;
        });
        moments.bad += w.bad, moments.checked += w.checked;
        if (moments.first.empty() && w.bad) moments.first = names[c] + " " + w.first;
    }
    if (moments.checked) moments.report(t, "moments", "m2_c ≥ c² in every pixel and channel");
    if (t.hasParameter("aovs")) {
        std::string aovs;
        for (const auto& [k, v] : t.configuration().params)
            if (k == "aovs") aovs = std::get<std::string>(v);
        if (aovs.empty())
            if (const ParamSpec* p = t.registry().info("renderer", t.component()).schema.find("aovs"); p && p->defaultValue)
                aovs = std::get<std::string>(*p->defaultValue);
        checkAovs(t, img, aovs);
    }
}

} // namespace effigi::conform
