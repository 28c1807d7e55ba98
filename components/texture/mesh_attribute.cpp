// texture "mesh_attribute" — a per-vertex or per-face attribute of the mesh hit, as a texture.
//
// Reads the TriangleMesh attribute `name` ("vertex_color", "face_color", "vertex_<x>",
// ... as PLY files store them, effigi/render/ply_reader.hpp) of the shape at the
// surface point: vertex attributes are blended with the hit's barycentrics (b0, b1, b2)
// = (1 − b1 − b2, primUV), face attributes are constant over the triangle. As in
// Mitsuba 3, a three-channel attribute whose name contains "color" is an RGB colour:
// each corner's value is upsampled to a spectrum (Jakob & Hanika 2019) BEFORE the blend
// (upsampling is not linear); other three-channel attributes read as their luminance.
// The result is multiplied by `scale`. A shape without the attribute (or without a
// mesh) reads 0: Mitsuba raises an error there, but the texture only meets the shape
// during rendering, where stopping is worse than a black surface.
//
// Parameters:
//   name   string  (required)  "vertex_<attr>" or "face_<attr>"
//   scale  float   1           factor on the value
//
// Reference: Mitsuba 3 `mesh_attribute` and Mesh::eval_attribute.
#include "texture_common.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/mesh.hpp"
#include "effigi/spectral/colorspace.hpp"

namespace effigi {
namespace {

class MeshAttributeTexture final : public Implements<ITexture> {
public:
    static Schema schema() {
        Schema s("texture", "mesh_attribute", "A per-vertex (interpolated) or per-face mesh attribute, e.g. PLY colours.");
        s.cite("Mitsuba 3 mesh_attribute");
        s.optional("name", ParamType::String, "Attribute name: 'vertex_<name>' or 'face_<name>' (e.g. vertex_color)")
            .isRequired();
        s.real("scale", 1.0, "Factor applied to the attribute value").range(0.0, 1e30);
        s.addConformance({"vertex colour", {{"name", std::string("vertex_color")}}});
        s.addConformance({"face colour scaled 0", {{"name", std::string("face_color")}, {"scale", 0.0}}});
        s.addConformance({"vertex scalar huge scale", {{"name", std::string("vertex_quality")}, {"scale", 1e30}}});
        return s;
    }

    explicit MeshAttributeTexture(const Properties& p)
        : m_name(p.getString("name")), m_scale(p.getFloat("scale")) {
        if (m_name.rfind("vertex_", 0) != 0 && m_name.rfind("face_", 0) != 0)
            failAt(p.whereOf("name"), "{}: attribute name '{}' must start with 'vertex_' or 'face_'", p.describe(),
                   excerpt(m_name));
        m_colour = m_name.find("color") != std::string::npos;
    }

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        Corners c;
        if (!corners(si, c)) return SampledSpectrum(0.f);
        if (c.attr->channels == 1) return SampledSpectrum(m_scale * c.blend1());
        if (!m_colour) return SampledSpectrum(m_scale * luminance(c.blend3()));
        const RGBToSpectrumTable& table = RGBToSpectrumTable::sRGB();
        SampledSpectrum s(0.f);
        for (int k = 0; k < 3; ++k)
            if (c.w[k] != 0.f) s += SpectralTexel::fromRGB(table, c.rgb(k)).eval(lambda) * c.w[k];
        return s * m_scale;
    }

    float evalFloat(const SurfaceInteraction& si) const override {
        Corners c;
        if (!corners(si, c)) return 0.f;
        return m_scale * (c.attr->channels == 1 ? c.blend1() : luminance(c.blend3()));
    }

    Vector3f evalVector(const SurfaceInteraction& si) const override {
        Corners c;
        if (!corners(si, c)) return Vector3f(0.f);
        return m_scale * (c.attr->channels == 1 ? Vector3f(c.blend1()) : c.blend3());
    }

    /// The mesh is not known before a lookup: colours are bounded by 1 (times scale),
    /// which is what the renderers' bounds assume for an attribute.
    float maxValue() const override { return m_scale; }
    float mean() const override { return 0.5f * m_scale; }

private:
    /// The three corner values and weights of the attribute at a hit.
    struct Corners {
        const MeshAttribute* attr = nullptr;
        std::size_t at[3] = {0, 0, 0};  // value offsets into attr->data
        float w[3] = {1.f, 0.f, 0.f};
        float blend1() const { return w[0] * attr->data[at[0]] + w[1] * attr->data[at[1]] + w[2] * attr->data[at[2]]; }
        Vector3f rgb(int k) const { return {attr->data[at[k]], attr->data[at[k] + 1], attr->data[at[k] + 2]}; }
        Vector3f blend3() const { return w[0] * rgb(0) + w[1] * rgb(1) + w[2] * rgb(2); }
    };

    bool corners(const SurfaceInteraction& si, Corners& c) const {
        const TriangleMesh* mesh = si.shape ? si.shape->mesh() : nullptr;
        if (!mesh) return false;
        c.attr = mesh->attribute(m_name);
        if (!c.attr || (c.attr->channels != 1 && c.attr->channels != 3)) return false;
        const std::size_t ch = std::size_t(c.attr->channels), tri = si.prim;
        if (tri >= mesh->triangleCount()) return false;
        if (c.attr->perFace) {
            c.at[0] = c.at[1] = c.at[2] = tri * ch;
            return true;
        }
        for (int k = 0; k < 3; ++k) c.at[k] = std::size_t(mesh->indices[3 * tri + std::size_t(k)]) * ch;
        float b1 = si.primUV.x, b2 = si.primUV.y;
        c.w[0] = std::max(0.f, 1.f - b1 - b2), c.w[1] = b1, c.w[2] = b2;
        return true;
    }

    static float luminance(const Vector3f& rgb) {
        static const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
        return dot(luma, rgb);
    }

    std::string m_name;
    float m_scale;
    bool m_colour = false;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MeshAttributeTexture)
