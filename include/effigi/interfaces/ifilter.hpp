#pragma once
// IFilter — a separable pixel reconstruction kernel: weight(x, y) = eval(x) · eval(y).
#include "effigi/core/component.hpp"

namespace effigi {

class IFilter : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IFilter");
    static constexpr const char* Tag = "rfilter";

    /// Support radius in pixels: eval(x) = 0 for |x| > radius().
    virtual float radius() const = 0;
    /// 1D kernel value at offset x (pixels) from the pixel centre.
    virtual float eval(float x) const = 0;
};

} // namespace effigi
