// texture "rawconstant" — a constant that is NOT a colour: one float or a 3-vector,
// returned as is, without RGB-to-spectrum upsampling.
//
// Normal maps (`normalmap`) read their texture with evalVector() as a direction encoded
// in [0, 1]³; a constant normal map must therefore hold the raw vector, which an <rgb>
// cannot (it would be turned into a reflectance spectrum). Read as a spectrum, the texture
// is flat at the mean of its components, as Mitsuba's `rawconstant` is for one float.
//
// Parameters:
//   value  vector (default 1, 1, 1)  the constant (Mitsuba also takes a <float> here;
//          effigi's schema types are single, so write <vector value="v, v, v"/>)
//
// Reference: Mitsuba 3 `rawconstant`.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <algorithm>

namespace effigi {
namespace {

class RawConstant final : public Implements<ITexture> {
public:
    static Schema schema() {
        Schema s("texture", "rawconstant", "A constant float or 3-vector returned without colour conversion.");
        s.cite("Mitsuba 3 rawconstant");
        s.vector("value", Vector3f(1.f), "The constant, returned as is (normal maps read it as a direction)");
        s.addConformance({"default", {}});
        s.addConformance({"flat normal", {{"value", VectorValue{{0.5f, 0.5f, 1.f}}}}});
        s.addConformance({"zero", {{"value", VectorValue{{0.f, 0.f, 0.f}}}}});
        s.addConformance({"huge", {{"value", VectorValue{{1e30f, 1e30f, 1e30f}}}}});
        return s;
    }

    explicit RawConstant(const Properties& p) : m_value(p.getVector("value")) {
        if (!isFinite(m_value)) failAt(p.whereOf("value"), "{}: parameter 'value' must be finite", p.describe());
        m_mean = (m_value.x + m_value.y + m_value.z) / 3.f;
    }

    SampledSpectrum eval(const SurfaceInteraction&, const SampledWavelengths&) const override {
        return SampledSpectrum(m_mean);
    }
    float evalFloat(const SurfaceInteraction&) const override { return m_mean; }
    Vector3f evalVector(const SurfaceInteraction&) const override { return m_value; }
    float maxValue() const override { return std::max({m_value.x, m_value.y, m_value.z}); }
    float mean() const override { return m_mean; }
    bool isConstant() const override { return true; }

private:
    Vector3f m_value;
    float m_mean = 1.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RawConstant)
