// medium "heterogeneous" — a medium whose extinction and albedo vary in space, read from
// nested volumes (a voxel grid from a file, or a constant): Mitsuba 3's `heterogeneous`.
//
// As there, σt(p) = scale · sigma_t(p) and σs = α(p) σt with α = albedo(p) (clamped to
// [0, 1]), and the medium ends at the bounding box of its sigma_t volume: outside that box
// σt = 0 (Mitsuba's volpath only tracks inside it). A plain number for sigma_t is a
// constvolume over the unit cube [0, 1]³, so give a volume with a `to_world` to fill a
// larger shape. No emission (Mitsuba 3's medium has none either).
//
// Majorants: a 16³ grid of bounds over sigma_t's box (majorant_grid.hpp), each cell
// holding scale × sigma_t's bound over the cell (IVolume::maxIn: the largest voxel in
// the cell's trilinear support, at every wavelength, RGB upsampling included), walked
// one cell per majorant() call by a 3-D DDA. Empty cells give zero-majorant pieces that
// trackers cross without a step. A constant sigma_t has one piece over its box with
// σ_maj = σt(λ) itself, per wavelength, so no null collisions.
//
// Parameters:
//   sigma_t          volume, float or spectrum (default 1, >= 0)   extinction [1/distance]
//   albedo           volume, float or spectrum (default 0.75, [0, 1])  σs/σt
//   scale            float (default 1, >= 0)   multiplies sigma_t (unit conversion)
//   sample_emitters  bool (default true)       renderers cast shadow rays from inside
//   phase            nested phase (default isotropic)
//   has_spectral_extinction  accepted as in Mitsuba, ignored (σt is always per wavelength)
//
// Reference: Mitsuba 3 documentation, "Heterogeneous medium (heterogeneous)"; E. R.
// Woodcock et al., ANL-7050, 1965 (delta tracking against a majorant).
#include "majorant_grid.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/interfaces/ivolume.hpp"

#include <optional>

namespace effigi {
namespace {

/// Cells per axis of the majorant grid: 4096 bounds, few enough to build in
/// milliseconds, fine enough that a plume's empty corners get their own cells.
constexpr int MajorantCells = 16;

/// A nested volume for the conformance configurations; absent (the configuration is then
/// left out) if it cannot be made, e.g. when effigi-conform runs outside the source tree.
std::optional<PropertyValue> nestedVolume(const std::string& type,
                                          const std::vector<std::pair<std::string, PropertyValue>>& params) {
    try {
        Properties p("volume", type);
        for (const auto& [name, value] : params) p.set(name, value);
        return ComponentValue{"volume", Registry::instance().create("volume", type, p)};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

class HeterogeneousMedium final : public Implements<IMedium> {
public:
    static Schema schema() {
        Schema s("medium", "heterogeneous",
                 "Heterogeneous participating medium: extinction and albedo from volumes (voxel grids or constants).");
        s.cite("Mitsuba 3 heterogeneous; J. Amanatides & A. Woo, A fast voxel traversal algorithm, Eurographics 1987");
        s.volume("sigma_t", 1.f, SpectrumKind::Unbounded, "Extinction coefficient σt per unit distance (a volume, "
                 "or a number over the unit cube)").atLeast(0.0);
        s.volume("albedo", 0.75f, SpectrumKind::Reflectance, "Single-scattering albedo σs/σt").range(0.0, 1.0);
        s.real("scale", 1.0, "Factor on sigma_t, for coefficients given in other units than the scene's").atLeast(0.0);
        s.boolean("sample_emitters", true, "Whether renderers sample emitters (shadow rays) from inside the medium");
        s.child("phase", "phase", "Phase function of the scattering events (default: isotropic)");
        s.ignored("has_spectral_extinction", "σt is evaluated at every sampled wavelength");
        addConfigurations(s);
        return s;
    }

    explicit HeterogeneousMedium(const Properties& p)
        : m_sigmaT(volume(p, "sigma_t")), m_albedo(volume(p, "albedo")), m_scale(p.getFloat("scale")),
          m_phase(p.get<IPhaseFunction>("phase")), m_sampleEmitters(p.getBool("sample_emitters")),
          m_bbox(m_sigmaT->bbox()) {
        if (!std::isfinite(m_scale * m_sigmaT->maxValue()))
            failAt(p.whereOf("scale"), "{}: scale × sigma_t reaches {} × {}; it must be finite", p.describe(), m_scale,
                   m_sigmaT->maxValue());
        // Grids are checked to be ≥ 0 where they are read; an albedo above 1 is data error.
        if (m_albedo->maxValue() > 1.f + 1e-4f)
            failAt(p.whereOf("albedo"), "{}: the albedo volume reaches {}; an albedo must lie in [0, 1]", p.describe(),
                   m_albedo->maxValue());
        if (!m_phase) {
            Properties d("phase", "isotropic", p.where());
            m_phase = query<IPhaseFunction>(Registry::instance().create("phase", "isotropic", d));
        }
        // A bound 1e-5 above the data's covers the rounding of a trilinear blend.
        const float scale = m_scale * (1.f + 1e-5f);
        const IVolume& sigmaT = *m_sigmaT;
        m_grid = MajorantGrid(m_bbox, sigmaT.isConstant() ? 1 : MajorantCells,
                              [&](const BBox3f& cell) { return scale * sigmaT.maxIn(cell); });
    }

    const IPhaseFunction& phase() const override { return *m_phase; }
    bool isHomogeneous() const override { return false; }
    bool sampleEmitters() const override { return m_sampleEmitters; }

    MediumProperties at(const Point3f& p, const SampledWavelengths& lambda) const override {
        MediumProperties mp;
        if (!inside(p)) return mp;
        const SampledSpectrum sigmaT = m_scale * m_sigmaT->eval(p, lambda);
        SampledSpectrum albedo = m_albedo->eval(p, lambda);
        for (int i = 0; i < NSpectrumSamples; ++i) albedo[i] = std::clamp(albedo[i], 0.f, 1.f);
        mp.sigmaS = sigmaT * albedo;
        mp.sigmaA = sigmaT * (SampledSpectrum(1.f) - albedo);
        return mp;
    }

    MajorantSegment majorant(const Ray& ray, float tMin, float tMax, const SampledWavelengths& lambda) const override {
        const MajorantGrid::Piece piece = m_grid.piece(ray, tMin, tMax);
        MajorantSegment seg{tMin, piece.tMax, SampledSpectrum(0.f)};
        if (!piece.inside) return seg;
        // A constant σt bounds itself at each wavelength (as in the homogeneous medium).
        seg.sigmaMaj = m_sigmaT->isConstant() ? m_scale * m_sigmaT->eval(ray(tMin), lambda) : SampledSpectrum(piece.bound);
        return seg;
    }

private:
    /// A parameter that takes a volume: the nested one, or a constvolume of the value.
    static Ref<IVolume> volume(const Properties& p, const std::string& name) {
        const Properties::Entry* e = p.find(name);
        if (std::holds_alternative<ComponentValue>(e->value)) return p.get<IVolume>(name);
        Properties c("volume", "constvolume", e->where);
        c.set("value", e->value, e->where);
        try {
            return query<IVolume>(Registry::instance().create("volume", "constvolume", c));
        } catch (const Error& err) {
            failAt(p.whereOf(name), "{}: parameter '{}': {}", p.describe(), name, err.what());
        }
    }

    bool inside(const Point3f& p) const {
        return p.x >= m_bbox.min.x && p.y >= m_bbox.min.y && p.z >= m_bbox.min.z && p.x <= m_bbox.max.x &&
               p.y <= m_bbox.max.y && p.z <= m_bbox.max.z;
    }

    static void addConfigurations(Schema& s);

    Ref<IVolume> m_sigmaT, m_albedo;
    float m_scale;
    Ref<IPhaseFunction> m_phase;
    bool m_sampleEmitters;
    BBox3f m_bbox;
    MajorantGrid m_grid;
};

void HeterogeneousMedium::addConfigurations(Schema& s) {
    // effigi-conform: Mitsuba's defaults (σt = 1 over the unit cube), and the grids of
    // tests/data/volume (gen: tests/test_media_grid.cpp) over [−1.5, 1.5]³, which holds the
    // origin of the suite's transmittance ray: a ramp (also nearest, dense and turned),
    // a sparse RGB grid (chromatic σt, empty cells) and a chromatic constant.
    s.addConformance({"default", {}});
    const Transform box = Transform::translate(Vector3f(-1.5f)) * Transform::scale(Vector3f(3.f));
    const std::string ramp = "tests/data/volume/ramp.vol", rgb = "tests/data/volume/rgb.vol";
    auto add = [&](const std::string& name, std::vector<std::pair<std::string, PropertyValue>> params,
                   const std::string& type, std::vector<std::pair<std::string, PropertyValue>> sigma) {
        if (auto v = nestedVolume(type, sigma)) {
            params.emplace_back("sigma_t", *v);
            s.addConformance({name, std::move(params)});
        }
    };
    add("ramp", {{"albedo", 0.8}}, "gridvolume", {{"filename", ramp}, {"to_world", box}});
    add("ramp nearest dense", {{"scale", 20.0}}, "gridvolume",
        {{"filename", ramp}, {"filter_type", std::string("nearest")}, {"to_world", box}});
    if (auto albedo = nestedVolume("gridvolume", {{"filename", ramp}, {"filter_type", std::string("nearest")}}))
        add("turned ramp albedo", {{"albedo", *albedo}}, "gridvolume",
            {{"filename", ramp}, {"wrap_mode", std::string("mirror")},
             {"to_world", Transform::rotate({1.f, 1.f, 0.f}, 40.f) * box}});
    add("rgb sparse", {{"albedo", RGBValue{{0.9f, 0.5f, 0.2f}}}, {"scale", 2.0}}, "gridvolume",
        {{"filename", rgb}, {"to_world", box}});
    SpectrumValue haze;  // σt falling from blue to red
    haze.lambdas = {360.f, 450.f, 550.f, 650.f, 830.f};
    haze.values = {4.f, 2.4f, 1.1f, 0.55f, 0.2f};
    add("chromatic constant", {}, "constvolume", {{"value", haze}, {"to_world", box}});
    s.addConformance({"vacuum", {{"sigma_t", 0.0}}});
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HeterogeneousMedium)
