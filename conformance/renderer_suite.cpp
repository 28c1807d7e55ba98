// Renderer suite: every IRenderer, in each of its configurations, renders the scenes of
// renderer_scenes.hpp, whose pixels have exact values (white furnace, a plane under a
// uniform sky, closed emitting enclosures of ρ = 0.5 to 0.99), at low resolution:
//  - stochastic renderers render each scene K times with independent seeds; the K image
//    means (of the grey (R + G + B)/3) are compared with the exact value by Student's
//    t-test (two-sided), so nothing is assumed about how pixels correlate (ptracer's light
//    paths splat into many pixels). Renderers declared unbiased (the table below) are
//    tested again at 8× the samples ("unbiased …"): small biases show there.
//  - renderers that keep a per-pixel variance (IRenderer::varianceEstimate) must predict
//    the spread of the K image means ("error bar …", χ² test of the variance ratio).
//  - renderers built on a radiosity solution (IRadiosityReport) must show the exact value
//    within the solver's reported error bound (area-weighted over the whole enclosure, so
//    divided by the fraction of the area the camera sees), plus what float form factors
//    allow: exactly where the image is deterministic (radiosity), by a t-test of the K
//    image means against that interval where it samples wavelengths (twopass).
//    Environment light is not part of a radiosity solution: those scenes are skipped.
//  - stochastic renderers skip the stiff enclosure (ρ = 0.99) beyond max_depth 16:
//    Mitsuba's Russian roulette gives it an estimator of infinite variance.
//  - wrappers (aov, moment) are checked through their first nested renderer; their own
//    channels by renderer_channels.cpp.
// The depth a renderer is limited to and whether it hides emitters come from its
// max_depth and hide_emitters parameters (Mitsuba's convention); renderers that follow no
// diffuse bounce (`direct`, `whitted`) are held to max_depth 2 at most: the scenes are diffuse.
// All statistical checks are seeded from the run's seed and their names.
#include "conformance/histogram.hpp"
#include "conformance/renderer_channels.hpp"
#include "conformance/renderer_scenes.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/render/radiosity_solution.hpp"

#include <fmt/format.h>

#include <cmath>

namespace effigi::conform {

namespace {

/// Renderers declared unbiased, with the reason. IRenderer has no such declaration yet;
/// until it has, the suite keeps this list (a renderer not in it is only held to the
/// exact value at the basic sample count).
struct Declaration {
    const char* name;
    const char* why;
};
const Declaration Unbiased[] = {
    {"path", "Monte Carlo path tracing; Russian roulette reweights the survivors (Veach 1997, ch. 9)"},
    {"volpath", "path tracing with delta tracking and spectral MIS (Miller et al. 2019); on the suite's surface "
                "scenes the same estimator as path with the balance heuristic"},
    {"direct", "MIS-weighted emitter and BSDF samples of direct lighting (Veach & Guibas 1995)"},
    {"ptracer", "light tracing with camera connections (Veach 1997, §4.A)"},
    {"pssmlt", "Kelemen's expected-value splatting from bootstrap-resampled starts (Kelemen et al. 2002)"},
    {"bdpt", "every join of a camera and a light subpath, MIS-weighted by the power heuristic (Veach 1997, ch. 10)"},
    {"whitted", "emitter samples of direct light at the end of delta chains chosen by BSDF sampling (Whitted 1980); "
                "unbiased for that transport, which on the suite's diffuse scenes is direct lighting"},
};
/// Renderers that follow no non-delta bounce (direct lighting, plus delta chains for
/// whitted): on the suite's scenes, all diffuse, they compute max_depth 2 at most.
const char* const DirectOnly[] = {"direct", "whitted"};
/// Wrappers whose colour image is their first nested renderer's, sample by sample.
const char* const Wrappers[] = {"aov", "moment"};

/// What the suite holds a configuration to.
struct Plan {
    std::string about;  ///< whose semantics: the component, or "nested path" for a wrapper
    Semantics semantics;
    const char* unbiased = nullptr;  ///< the reason, if declared unbiased
    bool colour = true;              ///< renders radiance (false: a wrapper without nested renderers)
};

std::optional<PropertyValue> paramOf(Registry& reg, const std::string& name, const ParamList& params,
                                     const std::string& key) {
    for (const auto& [k, v] : params)
        if (k == key) return v;
    const ParamSpec* p = reg.info("renderer", name).schema.find(key);
    return p ? p->defaultValue : std::nullopt;
}

Plan planOf(Registry& reg, const std::string& component, const ParamList& config) {
    std::string name = component;
    ParamList params = config;
    Plan plan;
    plan.about = component;
    if (std::find(std::begin(Wrappers), std::end(Wrappers), component) != std::end(Wrappers)) {
        // The first nested renderer, in the parameters its configuration was made with
        // (the wrappers' configurations nest renderers in their defaults).
        auto it = std::find_if(config.begin(), config.end(), [](const auto& e) {
            const auto* c = std::get_if<ComponentValue>(&e.second);
            return c && c->tag == "renderer" && c->object;
        });
        if (it == config.end()) {
            plan.colour = false;
            return plan;
        }
        const std::string& type = std::get<ComponentValue>(it->second).object->typeName();
        name = type.substr(type.find('/') + 1);
        params.clear();
        plan.about = "nested " + name;
    }
    if (auto d = paramOf(reg, name, params, "max_depth"); d && std::holds_alternative<std::int64_t>(*d))
        plan.semantics.depth = int(std::get<std::int64_t>(*d));
    if (std::find(std::begin(DirectOnly), std::end(DirectOnly), name) != std::end(DirectOnly)) {
        int& d = plan.semantics.depth;
        if (d < 0 || d > 2) d = 2;
    }
    if (auto h = paramOf(reg, name, params, "hide_emitters"); h && std::holds_alternative<bool>(*h))
        plan.semantics.hideEmitters = std::get<bool>(*h);
    for (const Declaration& d : Unbiased)
        if (name == d.name) plan.unbiased = d.why;
    return plan;
}

/// Two-sided p-value of Student's t with n degrees of freedom, by the finite series of
/// Abramowitz & Stegun 26.7.3 (n odd) and 26.7.4 (n even).
double studentPValue(double t, int n) {
    if (std::isnan(t)) return 0.0;
    const double theta = std::atan(std::abs(t) / std::sqrt(double(n))), c2 = std::cos(theta) * std::cos(theta);
    double a;
    if (n % 2 == 1) {
        double term = std::cos(theta), sum = n > 1 ? term : 0.0;
        for (int k = 3; k <= n - 2; k += 2) sum += term *= c2 * (k - 1) / k;
        a = 2.0 / 3.14159265358979323846 * (theta + std::sin(theta) * sum);
    } else {
        double term = 1.0, sum = 1.0;
        for (int k = 2; k <= n - 2; k += 2) sum += term *= c2 * (k - 1) / k;
        a = std::sin(theta) * sum;
    }
    return std::clamp(1.0 - a, 0.0, 1.0);
}

/// K renders of one scene: the image means and what the renderer said of its variance.
struct Renders {
    MeanVar grey, green;           // image means, over the renders
    double predictedGreen = 0.0;   // mean over renders of Var(image mean of G) from varianceEstimate
    bool variance = true;          // every render gave a variance estimate
    std::uint64_t bad = 0, pixels = 0;
    double emitted = 0.0;          // grey of the emitted radiance
    std::string solver;            // IRadiosityReport: the last solve's summary
    double errorBound = 0.0;
};

Renders render(Target& t, const AnalyticScene& s, int res, int spp, int runs, const std::string& key) {
    Registry& reg = t.registry();
    std::unique_ptr<Scene> scene = loadAnalytic(s, res, spp);
    ParamList overrides;
    // A radiosity renderer's default mesh (2000 elements) is more than a uniform
    // enclosure needs: 16 elements a face keep the suite quick.
    if (t.hasParameter("mesh") &&
        std::none_of(t.configuration().params.begin(), t.configuration().params.end(),
                     [](const auto& e) { return e.first == "mesh"; })) {
        Properties m("mesh", "uniform");
        m.set("element_count", std::int64_t(96));
        overrides.push_back({"mesh", ComponentValue{"mesh", reg.create("mesh", "uniform", m)}});
    }
    Ref<IRenderer> r = query<IRenderer>(t.create(overrides));  // fresh: solutions are cached per scene
    Renders out;
    out.emitted = emittedGrey(*scene);
    for (int k = 0; k < runs; ++k) {
        RenderControl control;
        control.progress = false;
        control.seed = t.derivedSeed(key) + std::uint64_t(k) * 0x9e3779b97f4a7c15ull;
        r->render(*scene, control);
        const Image img = scene->camera().film().develop();
        std::vector<double> grey = greyPixels(img);
        if (grey.empty()) throw std::runtime_error("the developed image has no R, G, B channels");
        double sum = 0.0, green = 0.0;
        int g = int(std::find(img.channelNames.begin(), img.channelNames.end(), "G") - img.channelNames.begin());
        for (std::size_t i = 0; i < grey.size(); ++i) {
            ++out.pixels;
            if (!(std::isfinite(grey[i]) && grey[i] >= 0.0)) ++out.bad;
            sum += grey[i];
            green += img.pixels[i * img.channels() + g];
        }
        out.grey.add(sum / grey.size());
        out.green.add(green / grey.size());
        std::vector<float> v;
        if (r->varianceEstimate(v) && v.size() == 3 * grey.size()) {
            double var = 0.0;
            for (std::size_t i = 0; i < grey.size(); ++i) var += v[3 * i + 1];
            out.predictedGreen += var / (double(grey.size()) * grey.size()) / runs;
        } else {
            out.variance = false;
        }
    }
    if (Ref<IRadiosityReport> rep = query<IRadiosityReport>(Ref<IComponent>(r))) {
        out.solver = rep->solverReport().summary();
        out.errorBound = rep->solverReport().errorBound;
    }
    return out;
}

void checkStochastic(Target& t, const Plan& plan, const AnalyticScene& s, double factor) {
    const int res = int(t.count(12, 8)), runs = int(t.count(24, 16)), spp = int(t.count(8, 4));
    auto test = [&](const std::string& check, int samples) {
        Renders r = render(t, s, res, samples, runs, check);
        const double exact = factor * r.emitted, se = r.grey.stderror(), diff = r.grey.mean - exact;
        double tStat = se > 0.0 ? diff / se : (std::abs(diff) <= 1e-6 * std::max(exact, 1e-3) ? 0.0 : INFINITY);
        t.test(check, studentPValue(tStat, runs - 1), fmt::format("t = {:.2f}", tStat),
               fmt::format("mean of {} renders ({}² px, {} spp): {:.6g} ± {:.2g}; exact {:.6g} ({:.6g} × Le) for {} at "
                           "max_depth {}{}; {} of {} pixel values not finite or negative",
                           runs, res, samples, r.grey.mean, se, exact, factor, plan.about, plan.semantics.depth,
                           plan.semantics.hideEmitters ? ", emitters hidden" : "", r.bad, r.pixels));
        return r;
    };
    Renders basic = test(s.name, spp);
    if (basic.bad) t.expect("finite " + s.name, false, fmt::format("{} bad of {}", basic.bad, basic.pixels));
    if (basic.variance && basic.predictedGreen > 0.0) {
        // (K − 1) s² / σ² is χ² with K − 1 degrees of freedom when σ² is the true variance.
        double x = (runs - 1) * basic.green.variance() / basic.predictedGreen;
        double cdf = stats::chi2Cdf(x, runs - 1), p = 2.0 * std::min(cdf, 1.0 - cdf);
        t.test("error bar " + s.name, p, fmt::format("ratio {:.2f}", basic.green.variance() / basic.predictedGreen),
               fmt::format("variance of the G image mean over {} renders {:.3g}, predicted by varianceEstimate {:.3g}",
                           runs, basic.green.variance(), basic.predictedGreen));
    }
    if (plan.unbiased) test("unbiased " + s.name, 8 * spp);
}

/// Renderers built on a radiosity solution: the image mean must lie within the solver's
/// error bound of the exact value. The bound is of Σ A|B − B*| / Σ A B* over the whole
/// mesh, so on the part the camera sees the error may be 1/seenArea times larger. The
/// bound is of the solution of the system as stored: form factors are floats, so a closed
/// enclosure's rows sum to 1 only to ~1e-7, an error the solution amplifies by 1/(1 − ρ),
/// about the exact multiple `factor` (radiosity shows 1.2e-7 · factor); FloatRows · factor
/// allows for it, ten times over. The scenes' spectra are flat, so the solution's spectral
/// bins hold them exactly. A renderer that samples wavelengths or paths from the solution
/// (twopass) adds noise: then the K image means are tested against the interval
/// exact · (1 ± allowed) with Student's t.
void checkSolution(Target& t, const AnalyticScene& s, double factor) {
    constexpr double FloatRows = 1e-6;
    const int runs = int(t.count(16, 8));
    Renders r = render(t, s, 8, 4, runs, s.name);
    const double exact = factor * r.emitted, allowed = r.errorBound / s.seenArea + FloatRows * std::max(factor, 1.0);
    const double err = std::abs(r.grey.mean - exact) / exact, se = r.grey.stderror() / exact;
    const std::string detail = fmt::format("image mean {:.7g} ± {:.2g} over {} renders, exact {:.7g} ({:.6g} × Le); {}",
                                           r.grey.mean, r.grey.stderror(), runs, exact, factor, r.solver);
    if (r.bad) t.expect("finite " + s.name, false, fmt::format("{} bad of {}", r.bad, r.pixels));
    if (!(se > 0.0)) {
        t.expect("within bound " + s.name, err <= allowed, fmt::format("error {:.3g} ≤ {:.3g}", err, allowed), detail);
        return;
    }
    const double excess = std::max(0.0, err - allowed) / se;
    t.test("within bound " + s.name, studentPValue(excess, runs - 1), fmt::format("error {:.3g}, allowed {:.3g}", err, allowed),
           detail);
}

void runRendererSuite(Target& t) {
    if (!t.as<IRenderer>()) {
        t.expect("interface", false, "-", "component does not implement IRenderer");
        return;
    }
    const bool solution = query<IRadiosityReport>(t.object()) != nullptr;
    Plan plan = planOf(t.registry(), t.component(), t.configuration().params);
    if (!solution && plan.colour)
        t.info("declared", plan.unbiased ? "unbiased" : "not declared unbiased", plan.unbiased ? plan.unbiased : "");
    for (const AnalyticScene& s : analyticScenes(t.quick())) {
        if (!plan.colour) break;
        if (solution && s.environment) {
            t.skip(s.name, "environment light is not part of a radiosity solution");
            continue;
        }
        std::optional<double> factor = s.exact(solution ? Semantics{} : plan.semantics);
        if (!factor) {
            t.skip(s.name, s.why);
            continue;
        }
        const int depth = plan.semantics.depth;
        if (!solution && s.stochasticDepth >= 0 && (depth < 0 || depth > s.stochasticDepth)) {
            t.skip(s.name, s.stochasticWhy);
            continue;
        }
        if (solution) checkSolution(t, s, *factor);
        else checkStochastic(t, plan, s, *factor);
    }
    checkChannels(t, plan.colour);
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("renderer",
                         "exact pixel values of furnace, sky and enclosure scenes (t-test over seeded renders; radiosity "
                         "within its error bound), calibrated variance, wrappers' channels",
                         effigi::conform::runRendererSuite);
