// Load-time checks of the scene's coordinate range (effigi/render/scene_range.hpp).
#include "effigi/render/scene_range.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <fmt/format.h>

#include <cmath>

namespace effigi {

namespace {

/// "x = 1e+38" for the first coordinate of p that is not finite or out of range.
std::string offendingAxis(const Point3f& p) {
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(p[k]) <= MaxSceneCoordinate)) return fmt::format("{} = {:g}", "xyz"[k], p[k]);
    return {};
}

} // namespace

bool inSceneRange(const Point3f& p) {
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(p[k]) <= MaxSceneCoordinate)) return false;  // also false for NaN
    return true;
}

std::string shapeRangeProblem(const IShape& shape) {
    const BBox3f b = shape.bbox();
    // An empty box (no geometry) is no problem; a NaN one is, and fails valid() too, so
    // look at the corners whatever valid() says unless both are the empty defaults.
    if (b.min == Point3f(Infinity) && b.max == Point3f(-Infinity)) return {};
    for (const Point3f& p : {b.min, b.max})
        if (!inSceneRange(p))
            return fmt::format("its bounds reach {}, beyond effigi's coordinate range ±{:g} (a ray leaving it "
                               "would be invalid for the accelerator)",
                               offendingAxis(p), MaxSceneCoordinate);
    return {};
}

std::string cameraRangeProblem(const ICamera& camera) {
    // A camera without a film (a test double) is probed over the unit square.
    Vector2f size(1.f);
    try {
        size = Vector2f(camera.film().fullSize());
    } catch (const Error&) {
    }
    const Point2f film[] = {{0.f, 0.f}, {size.x, 0.f}, {0.f, size.y}, {size.x, size.y}, 0.5f * size};
    const Point2f lens[] = {{0.f, 0.f}, {1.f, 1.f}, {0.5f, 0.5f}};
    const SampledWavelengths lambda = SampledWavelengths::constant(550.f);
    for (const Point2f& f : film)
        for (const Point2f& l : lens) {
            SampledSpectrum weight(1.f);
            const Ray ray = camera.generateRay({f, l, 0.f}, lambda, weight);
            if (!inSceneRange(ray.o))
                return fmt::format("its rays start at {}, beyond effigi's coordinate range ±{:g}",
                                   offendingAxis(ray.o), MaxSceneCoordinate);
            if (!isFinite(ray.d) || std::isnan(ray.tMax))
                return "it generates rays with a non-finite direction or length";
        }
    return {};
}

} // namespace effigi
