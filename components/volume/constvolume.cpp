// volume "constvolume" — the same value at every point: Mitsuba 3's `constvolume`, and
// what a heterogeneous medium makes of a plain <float>, <rgb> or <spectrum> given for a
// parameter that takes a volume.
//
// Its domain is still the unit cube placed by `to_world` (Mitsuba's Volume base class
// gives every volume that box, and its `heterogeneous` medium ends at the box of its
// sigma_t volume); the value does not depend on the point, inside the box or out.
// An RGB value with every channel in [0, 1] is upsampled with the bounded fit (so an
// albedo stays ≤ 1 at every wavelength), a brighter one as an unbounded colour, like
// the voxels of an RGB grid (grid_common.hpp). evalFloat is the mean over 360–830 nm
// (Mitsuba's eval_1 reads its texture's mean).
//
// Parameters:
//   value     float, rgb or spectrum (default 1, >= 0)   the constant
//   to_world  transform                                   places the unit cube (the bbox)
//
// Reference: Mitsuba 3 documentation, "Constant-valued volume data source (constvolume)".
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ivolume.hpp"

namespace effigi {
namespace {

class ConstVolume final : public Implements<IVolume> {
public:
    static Schema schema() {
        Schema s("volume", "constvolume", "A volume with the same value everywhere.");
        s.cite("Mitsuba 3 constvolume");
        s.spectrum("value", 1.f, SpectrumKind::Unbounded, "The constant (a float, rgb or spectrum)").atLeast(0.0);
        s.transform("to_world", "Places the unit cube [0,1]^3 (the volume's bounding box) in the world");
        s.addConformance({"default", {}});
        s.addConformance({"rgb", {{"value", RGBValue{{0.9f, 0.5f, 0.1f}}}}});
        s.addConformance({"bright rgb", {{"value", RGBValue{{40.f, 2.f, 0.f}}}}});
        SpectrumValue chromatic;
        chromatic.lambdas = {360.f, 550.f, 830.f};
        chromatic.values = {3.f, 0.5f, 7.f};
        s.addConformance({"spectrum", {{"value", chromatic},
                                       {"to_world", Transform::translate({-1.f, 2.f, 0.f}) * Transform::scale({3.f, 0.1f, 2.f})}}});
        s.addConformance({"zero", {{"value", 0.0}}});
        return s;
    }

    explicit ConstVolume(const Properties& p) : m_value(readValue(p)), m_toWorld(p.getTransform("to_world")) {
        double sum = 0.0;
        int count = 0;
        for (float lambda = LambdaMin; lambda <= LambdaMax; lambda += 1.f, ++count) {
            const float v = m_value(lambda);
            if (!(v >= 0.f) || !std::isfinite(v))
                failAt(p.whereOf("value"), "{}: parameter 'value' is {} at {} nm; it must be finite and >= 0",
                       p.describe(), v, lambda);
            sum += v;
        }
        m_mean = float(sum / count);
        m_max = std::max(m_value.maxValue(), m_mean);
        if (!m_toWorld.isFinite())
            failAt(p.whereOf("to_world"), "{}: parameter 'to_world' must be finite", p.describe());
        for (int c = 0; c < 8; ++c) m_bbox.expand(m_toWorld.point(Point3f(c & 1, (c >> 1) & 1, (c >> 2) & 1)));
    }

    SampledSpectrum eval(const Point3f&, const SampledWavelengths& lambda) const override {
        return m_value.sample(lambda);
    }
    float evalFloat(const Point3f&) const override { return m_mean; }
    float maxValue() const override { return m_max; }
    BBox3f bbox() const override { return m_bbox; }
    Transform toWorld() const override { return m_toWorld; }
    bool isConstant() const override { return true; }

private:
    static Spectrum readValue(const Properties& p) {
        const Properties::Entry* e = p.find("value");
        const auto* rgb = e ? std::get_if<RGBValue>(&e->value) : nullptr;
        const bool bounded = rgb && maxComponent(rgb->v) <= 1.f;
        return p.getSpectrum("value", bounded ? SpectrumKind::Reflectance : SpectrumKind::Unbounded);
    }

    Spectrum m_value;
    Transform m_toWorld;
    BBox3f m_bbox;
    float m_mean = 0.f, m_max = 0.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ConstVolume)
