// bsdf "normalmap" — a nested BSDF seen through a normal map: the shading normal is read
// from a texture whose raw RGB encodes a unit vector in the (tangent-space) shading frame,
// n = 2 rgb − 1, as Mitsuba 3's `normalmap`. The perturbed tangent is the original
// tangent made orthogonal to n (Gram–Schmidt), so a flat map (0.5, 0.5, 1) is the nested
// BSDF itself. The frame change, the cosine ratio, the side checks, flip_invalid_normals and the
// bump-terminator shadowing are shared with bumpmap (perturbed_frame.hpp, which explains
// them and where effigi departs from Mitsuba).
//
// Parameters (as Mitsuba 3):
//   normalmap               texture (required)  raw RGB normal map (a bitmap with raw="true",
//                                              or a constant <rgb>, read unconverted)
//   bsdf                    nested bsdf (required)
//   flip_invalid_normals    bool (default true)
//   use_shadowing_function  bool (default true)
//
// Reference: Mitsuba 3 documentation, "Normal map BSDF (normalmap)"; J. Estevez et al.,
// "A Microfacet-Based Shadowing Function to Solve the Bump Terminator Problem", Ray
// Tracing Gems (2019).
#include "perturbed_frame.hpp"

#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class NormalMap final : public PerturbedFrameBSDF {
public:
    static Schema schema() {
        Schema s("bsdf", "normalmap", "Normal-mapped adapter: a nested BSDF in the shading frame of a normal map.");
        s.cite("Mitsuba 3 documentation, Normal map BSDF; J. Estevez et al., A Microfacet-Based Shadowing Function "
               "to Solve the Bump Terminator Problem, Ray Tracing Gems, 2019");
        ParamSpec& map = s.texture("normalmap", 0.5f, SpectrumKind::Unbounded,
                                   "Normal map: raw RGB in [0, 1]³ encoding n = 2 rgb − 1 in the shading frame");
        map.defaultValue.reset();  // required, as in Mitsuba
        map.isRequired();
        declarePerturbedFrame(s);
        // effigi-conform: flat maps (the nested BSDF itself) over a diffuse, a glossy and a
        // specular BSDF, with Mitsuba's options and with both off. A tilted
        // normal makes any shading-normal BSDF non-reciprocal (perturbed_frame.hpp), which
        // the suite would reject: tests/test_bsdf_extra.cpp checks those cases instead.
        auto diffuse = nestedBSDF("diffuse");
        auto rough = nestedBSDF("roughconductor", {{"distribution", std::string("ggx")}, {"alpha", 0.3}});
        auto mirror = nestedBSDF("conductor");
        RGBValue flat{{0.5f, 0.5f, 1.f}};
        if (diffuse) {
            s.addConformance({"flat diffuse", {{"bsdf", *diffuse}, {"normalmap", flat}}});
            s.addConformance({"flat diffuse, options off", {{"bsdf", *diffuse}, {"normalmap", flat},
                                                             {"flip_invalid_normals", false},
                                                             {"use_shadowing_function", false}}});
        }
        if (rough) s.addConformance({"flat roughconductor", {{"bsdf", *rough}, {"normalmap", flat}}});
        if (mirror) s.addConformance({"flat conductor", {{"bsdf", *mirror}, {"normalmap", flat}}});
        return s;
    }

    explicit NormalMap(const Properties& p) : PerturbedFrameBSDF(p), m_map(p.getTexture("normalmap", SpectrumKind::Unbounded)) {
        // A constant <rgb> is a spectrum to getTexture; the map needs the raw triple.
        const Properties::Entry* e = p.find("normalmap");
        if (auto* rgb = std::get_if<RGBValue>(&e->value)) m_constant = rgb->v;
        else if (auto* v = std::get_if<double>(&e->value)) m_constant = Vector3f(float(*v));
    }

protected:
    Frame frame(const SurfaceInteraction& si, const Vector3f& wo) const override {
        Vector3f rgb = m_constant ? *m_constant : m_map->evalVector(si);
        return completeFrame(2.f * rgb - Vector3f(1.f), wo, Vector3f(1.f, 0.f, 0.f));
    }

private:
    Ref<ITexture> m_map;
    std::optional<Vector3f> m_constant;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::NormalMap)
