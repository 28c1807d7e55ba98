// texture "checkerboard" — two alternating colours on a 2x2 grid of the unit (u, v) square.
//
// With (u', v') = to_uv(u, v) and a = frac(u') > ½, b = frac(v') > ½, the texture is
// color0 where a == b and color1 elsewhere: one period per unit of u and v, color0 on
// the square at the origin. This is the pattern of Mitsuba 3's `eval` (its scalar
// `eval_1` swaps the colours, which looks like an oversight there; effigi uses the one
// pattern for every reading, so a roughness map and a colour map line up).
// color0 / color1 are themselves textures (constants usually), evaluated at the same point.
//
// Parameters:
//   color0  texture (reflectance, default 0.4)
//   color1  texture (reflectance, default 0.2)
//   to_uv   transform  affine map applied to (u, v) first
//
// Reference: Mitsuba 3 `checkerboard`.
#include "texture_common.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class Checkerboard final : public Implements<ITexture> {
public:
    static Schema schema() {
        Schema s("texture", "checkerboard", "Checkerboard of two colours, one period per unit of u and v.");
        s.cite("Mitsuba 3 checkerboard");
        // No range: Mitsuba's texture takes any value (its test scenes use 1.4), and the
        // consumer (a BSDF's reflectance, an emitter's radiance) decides what is physical.
        s.texture("color0", 0.4f, SpectrumKind::Reflectance, "Colour of the squares at the origin and diagonally from it");
        s.texture("color1", 0.2f, SpectrumKind::Reflectance, "Colour of the other squares");
        s.transform("to_uv", "Affine transform applied to the texture coordinates first");
        s.addConformance({"default", {}});
        s.addConformance({"black and white", {{"color0", 0.0}, {"color1", 1.0}}});
        s.addConformance({"saturated", {{"color0", RGBValue{{1.f, 0.f, 0.f}}}, {"color1", RGBValue{{0.f, 0.f, 1.f}}}}});
        s.addConformance({"huge values tiled 1000", {{"color0", 1e6}, {"color1", 0.0},
                                                     {"to_uv", Transform::scale({1e3f, 1e3f, 1.f})}}});
        return s;
    }

    explicit Checkerboard(const Properties& p)
        : m_color{p.getTexture("color0", SpectrumKind::Reflectance), p.getTexture("color1", SpectrumKind::Reflectance)},
          m_uv(UVTransform::read(p, "to_uv")) {}

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return pick(si).eval(si, lambda);
    }
    float evalFloat(const SurfaceInteraction& si) const override { return pick(si).evalFloat(si); }
    Vector3f evalVector(const SurfaceInteraction& si) const override { return pick(si).evalVector(si); }
    /// Piecewise constant between the square edges (where it is not differentiable).
    Vector2f evalFloatGradient(const SurfaceInteraction&) const override { return Vector2f(0.f); }

    float maxValue() const override { return std::max(m_color[0]->maxValue(), m_color[1]->maxValue()); }
    /// The two colours cover equal areas.
    float mean() const override { return 0.5f * (m_color[0]->mean() + m_color[1]->mean()); }

    /// Which colour covers (u, v): exposed through the pattern for the tests.
    static int square(const Point2f& uv) {
        bool a = uv.x - std::floor(uv.x) > 0.5f, b = uv.y - std::floor(uv.y) > 0.5f;
        return a == b ? 0 : 1;
    }

private:
    const ITexture& pick(const SurfaceInteraction& si) const { return *m_color[square(m_uv.apply(si.uv))]; }

    Ref<ITexture> m_color[2];
    UVTransform m_uv;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Checkerboard)
