// Pathgenerator suite: the box scene, and sampleDirection against pdfDirection by
// chi-square at a point of each material, for wo at normal, oblique and (for the
// dielectrics) inside incidence, in radiance and importance transport. The grid is
// (φ, cos θ) over the whole sphere of local directions; draws of delta lobes and walks
// ended at the surface fall outside every cell, which expects n (1 − ∫pdfDirection).
// Also checked per draw: its pdf equals pdfDirection(wo, wi) and its f the BSDF's f.
#include "conformance/histogram.hpp"
#include "conformance/pathgenerator_common.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <cmath>
#include <numbers>

namespace effigi::conform::pathgen {

namespace {

constexpr const char* BoxScene = R"(<scene version="3.0.0">
  <sensor type="perspective"><float name="fov" value="70"/>
    <transform name="to_world"><lookat origin="0, 0, 0.9" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
  <shape type="cube"><boolean name="flip_normals" value="true"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.6, 0.5"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/>
      <translate y="0.99"/></transform>
    <emitter type="area"><rgb name="radiance" value="4, 4, 3"/></emitter></shape>
  <emitter type="point"><point name="position" x="0.6" y="0.6" z="0.6"/><rgb name="intensity" value="1, 1, 1"/></emitter>
  <shape type="sphere" id="conductor"><point name="center" x="-0.5" y="-0.6" z="-0.4"/><float name="radius" value="0.3"/>
    <bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.3"/></bsdf></shape>
  <shape type="sphere" id="roughglass"><point name="center" x="0.5" y="-0.6" z="-0.4"/><float name="radius" value="0.3"/>
    <bsdf type="roughdielectric"><float name="alpha" value="0.4"/></bsdf></shape>
  <shape type="sphere" id="glass"><point name="center" x="0.5" y="0.4" z="-0.5"/><float name="radius" value="0.25"/>
    <bsdf type="dielectric"/></shape>
  <shape type="sphere" id="plastic"><point name="center" x="-0.5" y="0.4" z="-0.5"/><float name="radius" value="0.25"/>
    <bsdf type="plastic"/></shape>
</scene>)";

struct Material {
    const char* name;
    Point3f center;
    bool transmits;
};
const Material Materials[] = {{"diffuse wall", Point3f(0.f, -1.f, 0.f), false},
                              {"roughconductor", Point3f(-0.5f, -0.6f, -0.4f), false},
                              {"roughdielectric", Point3f(0.5f, -0.6f, -0.4f), true},
                              {"dielectric", Point3f(0.5f, 0.4f, -0.5f), true},
                              {"plastic", Point3f(-0.5f, 0.4f, -0.5f), false}};

/// The surface point seen from the middle of the box toward `target`.
bool surfacePoint(const Scene& scene, const Point3f& target, SurfaceInteraction& si) {
    const Point3f o(0.f, 0.1f, 0.2f);
    return scene.intersect(Ray{o, normalize(target - o)}, si) && si.bsdf;
}

void checkOne(Target& t, const IPathGenerator& g, const SurfaceInteraction& si, const std::string& name,
              const Vector3f& wo, TransportMode mode, Tally& perDraw) {
    constexpr double TwoPi = 2.0 * std::numbers::pi;
    const Grid2D grid = sphereGrid(t.quick() ? 16 : 32, t.quick() ? 16 : 32);
    const std::uint64_t n = t.count(200000, 50000);
    PCG32 rng = t.rng(name);
    const SampledWavelengths lambda = SampledWavelengths::sampleUniform(rng.nextFloat());
    std::vector<double> observed(std::size_t(grid.cells()), 0.0);
    double outside = 0.0;
    for (std::uint64_t i = 0; i < n; ++i) {
        SampledWavelengths l = lambda;
        auto s = g.sampleDirection(si, wo, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()), l, mode);
        double phi, cosTheta;
        if (!s || !(s->pdf > 0.f) || s->isSpecular() || (s->flags & BSDFNull)) {
            outside += 1.0;
            continue;
        }
        const float pdf = g.pdfDirection(si, wo, s->wi, lambda, mode);
        const SampledSpectrum f = si.bsdf->f(si, wo, s->wi, lambda, mode);
        double err = relativeError(s->pdf, pdf);
        for (int k = 0; k < NSpectrumSamples; ++k) err = std::max(err, relativeError(s->f[k], f[k], 1e-6));
        perDraw.worst = std::max(perDraw.worst, std::isnan(err) ? 1e9 : err);
        perDraw.note(err <= 1e-3, fmt::format("{}: wi = {}: pdf {} vs pdfDirection {}, f {} vs {}", name, vec(s->wi),
                                              s->pdf, pdf, spec(s->f), spec(f)));
        sphericalCoordinates(s->wi, phi, cosTheta);
        const int cell = grid.cellOf(phi, cosTheta);
        if (cell < 0) outside += 1.0;
        else observed[std::size_t(cell)] += 1.0;
    }
    const std::vector<double> cells = integrateCells(
        grid,
        [&](double phi, double c) { return double(g.pdfDirection(si, wo, sphericalDirection(phi, c), lambda, mode)); },
        1e-4 / grid.cells());
    const FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
    t.test("chi-square " + name, fit.chi2.pValue, fmt::format("p = {:.3g}", fit.chi2.pValue),
           fmt::format("{} draws over (φ, cos θ) ∈ [0, {:.4g}] × [−1, 1]; {}", n, TwoPi, fit.summary()), fit.histogram);
}

} // namespace

std::unique_ptr<Scene> loadBoxScene() { return loadScene(*xml::parseString(BoxScene, "pathgenerator suite: box")); }

PathContext makeContext(const Scene& scene, const IPathGenerator& g, int maxDepth, int rrDepth) {
    return makePathContext(scene, maxDepth, rrDepth, g, "the pathgenerator suite");
}

void checkDirectionDistribution(Target& t, const IPathGenerator& g, const Scene& scene) {
    Tally perDraw;
    for (const Material& m : Materials) {
        SurfaceInteraction si;
        if (!surfacePoint(scene, m.center, si)) {
            t.expect(fmt::format("chi-square {}", m.name), false, "-", "the suite's ray missed the material");
            continue;
        }
        std::vector<std::pair<std::string, Vector3f>> wos = {{"normal", Vector3f(0.f, 0.f, 1.f)},
                                                             {"oblique", normalize(Vector3f(0.8f, 0.1f, 0.3f))}};
        if (m.transmits) wos.push_back({"inside", normalize(Vector3f(-0.3f, 0.2f, -0.9f))});
        for (const auto& [where, wo] : wos)
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                // --quick: oblique incidence, importance transport at the dielectrics only.
                if (t.quick() && (where != "oblique" || (mode == TransportMode::Importance && !m.transmits))) continue;
                checkOne(t, g, si, fmt::format("{} wo {} {}", m.name, where, modeName(mode)), wo, mode, perDraw);
            }
    }
    t.expect("draws", perDraw.bad == 0, fmt::format("max rel. error {:.2g}", perDraw.worst),
             perDraw.detail("each non-delta draw: pdf = pdfDirection(wo, wi), f = the BSDF's f (1e-3)"));
}

} // namespace effigi::conform::pathgen
