// bsdf "bumpmap" — a nested BSDF on a surface displaced by a height texture h(u, v) along
// its normal, as Mitsuba 3's `bumpmap`: only the shading normal changes (Blinn 1978). The
// displaced point p + s h n has, to first order in the height (its curvature terms
// dropped, as Blinn and Mitsuba do),
//   ∂p'/∂u = ∂p/∂u (tangential part) + s ∂h/∂u n,   ∂p'/∂v likewise,
//   n' = ∂p'/∂u × ∂p'/∂v, turned to the side of the geometric normal;
// the perturbed tangent is ∂p/∂u made orthogonal to n'. A constant height is the nested BSDF
// itself. The frame change, side checks, flip_invalid_normals and shadowing are shared with
// normalmap (perturbed_frame.hpp). Where the shape gives no (u, v) derivatives (zero
// dp/du) the shading tangent and bitangent stand in for them (unit parametrisation).
//
// Parameters (as Mitsuba 3):
//   (texture)               nested texture, any name (required)  the height h (bitmap, raw="true")
//   scale                   float (default 1)                    s, multiplies the height
//   bsdf                    nested bsdf (required)
//   flip_invalid_normals    bool (default true)
//   use_shadowing_function  bool (default true)
//
// References: J. F. Blinn, "Simulation of Wrinkled Surfaces", SIGGRAPH 1978; Mitsuba 3
// documentation, "Bump map BSDF adapter (bumpmap)".
#include "perturbed_frame.hpp"

#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/constant_texture.hpp"

namespace effigi {
namespace {

class BumpMap final : public PerturbedFrameBSDF {
public:
    static Schema schema() {
        Schema s("bsdf", "bumpmap", "Bump-mapped adapter: a nested BSDF with the shading normal of a height texture.");
        s.cite("J. F. Blinn, Simulation of Wrinkled Surfaces, SIGGRAPH 1978; Mitsuba 3 documentation, Bump map BSDF");
        s.children("texture", "The height texture h(u, v) (exactly one, any name; a bitmap with raw=\"true\")");
        s.real("scale", 1.0, "Factor s on the height (bump strength)").range(-1e6, 1e6);
        declarePerturbedFrame(s);
        // effigi-conform: a constant height (the nested BSDF itself) over a diffuse, a glossy
        // and a specular BSDF, with Mitsuba's defaults and with a huge scale. Heights with
        // a gradient need a varying texture: tests/test_bsdf_extra.cpp checks those.
        auto flatHeight = ComponentValue{"texture", std::make_shared<ConstantTexture>(Spectrum(0.3f))};
        auto diffuse = nestedBSDF("diffuse");
        auto rough = nestedBSDF("roughconductor", {{"distribution", std::string("ggx")}, {"alpha", 0.3}});
        auto mirror = nestedBSDF("conductor");
        if (diffuse) s.addConformance({"flat diffuse", {{"bsdf", *diffuse}, {"height", flatHeight}}});
        if (rough)
            s.addConformance(
                {"flat roughconductor scale 1e6", {{"bsdf", *rough}, {"height", flatHeight}, {"scale", 1e6}}});
        if (mirror) s.addConformance({"flat conductor", {{"bsdf", *mirror}, {"height", flatHeight}}});
        return s;
    }

    explicit BumpMap(const Properties& p) : PerturbedFrameBSDF(p), m_scale(p.getFloat("scale")) {
        std::vector<Ref<IComponent>> textures = p.components("texture");
        if (textures.size() != 1)
            failAt(p.where(), "{}: give exactly one nested texture (the height), found {}", p.describe(),
                   textures.size());
        m_height = query<ITexture>(textures.front());
        if (!m_height) failAt(p.where(), "{}: the nested texture is not a texture", p.describe());
    }

protected:
    Frame frame(const SurfaceInteraction& si, const Vector3f& wo) const override {
        Vector3f du = si.toLocal(si.dpdu), dv = si.toLocal(si.dpdv);
        if (!(dot(du, du) > 0.f) || !(dot(dv, dv) > 0.f)) {
            du = Vector3f(1.f, 0.f, 0.f);
            dv = Vector3f(0.f, 1.f, 0.f);
        }
        Vector2f grad = m_scale * m_height->evalFloatGradient(si);
        // Tangential parts of ∂p/∂u, ∂p/∂v plus the height's slope along the normal (+z).
        Vector3f n = cross(Vector3f(du.x, du.y, grad.x), Vector3f(dv.x, dv.y, grad.y));
        if (dot(n, si.toLocal(si.n)) < 0.f) n = -n;
        return completeFrame(n, wo, du);
    }

private:
    float m_scale;
    Ref<ITexture> m_height;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BumpMap)
