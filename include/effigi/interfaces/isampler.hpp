#pragma once
// ISampler — points in [0,1)^n, one sequence per pixel and sample index, consumed a
// dimension at a time. Each rendering thread works on its own clone().
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"

#include <cstdint>

namespace effigi {

class ISampler : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ISampler");
    static constexpr const char* Tag = "sampler";

    virtual int samplesPerPixel() const = 0;
    /// Select the sequence of a pixel (or any integration domain keyed by two ints).
    virtual void startPixel(const Point2i& pixel) = 0;
    /// Start sample `index` of the current pixel at dimension 0.
    virtual void startSample(std::uint64_t index) = 0;

    virtual float get1D() = 0;
    virtual Point2f get2D() = 0;
    /// The film-position sample (some samplers stratify it specially).
    virtual Point2f getPixel2D() { return get2D(); }

    /// An independent copy for another thread, reseeded by `streamOffset`.
    virtual Ref<ISampler> clone(std::uint64_t streamOffset) const = 0;
};

} // namespace effigi
