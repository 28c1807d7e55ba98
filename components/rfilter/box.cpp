/*
 * rfilter "box" — the box (pixel-average) reconstruction filter.
 *
 *   eval(x) = 1 for |x| <= 1/2, else 0;   radius 1/2.
 *
 * With this radius every sample lands in exactly the one pixel that contains it, so
 * the film shows each pixel's plain sample mean: no blur and no correlation between
 * neighbouring pixels, at the price of aliasing (the box's spectrum is a sinc with
 * slowly decaying side lobes).
 *
 * Parameters: none (as Mitsuba 3's box).
 * Reference: M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed.,
 * 2023, §8.8 "Image Reconstruction".
 */
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <cmath>

namespace effigi {
namespace {

class BoxFilter final : public Implements<IFilter> {
public:
    static Schema schema() {
        Schema s("rfilter", "box", "Box filter of radius 1/2: each sample weighs only its own pixel.");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., 2023, §8.8");
        return s;
    }
    explicit BoxFilter(const Properties&) {}

    float radius() const override { return 0.5f; }
    float eval(float x) const override { return std::abs(x) <= 0.5f ? 1.f : 0.f; }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BoxFilter)
