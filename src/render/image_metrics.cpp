#include "effigi/render/image_metrics.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

namespace {
void checkComparable(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        fail("images differ in size: {}x{} against a {}x{} reference", a.width, a.height, b.width, b.height);
    if (a.channels() < 3 || b.channels() < 3) fail("error metrics need at least three channels (R, G, B)");
}
} // namespace

ErrorMetrics compareImages(const Image& image, const Image& reference) {
    checkComparable(image, reference);
    double se = 0.0, rel = 0.0, ae = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double v = image.at(x, y, c), r = reference.at(x, y, c), d = v - r;
                se += d * d;
                rel += d * d / (r * r + RelMSEEpsilon);
                ae += std::abs(d);
            }
    double n = 3.0 * image.width * image.height;
    return {std::sqrt(se / n), rel / n, ae / n};
}

double estimatedRelMSE(const Image& image, const std::vector<float>& rgbVariance) {
    std::size_t pixels = std::size_t(image.width) * image.height;
    if (rgbVariance.size() != 3 * pixels)
        fail("variance estimate has {} values, the image {} pixels x 3", rgbVariance.size(), pixels);
    if (image.channels() < 3) fail("error metrics need at least three channels (R, G, B)");
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double v = rgbVariance[(std::size_t(y) * image.width + x) * 3 + c], m = image.at(x, y, c);
                if (!std::isfinite(v)) return v;  // a pixel with fewer than two samples: unknown
                sum += v / (m * m + RelMSEEpsilon);
            }
    return pixels ? sum / double(3 * pixels) : 0.0;
}

double filterVarianceFactor(const IFilter& filter) {
    // Midpoint rule over the support; 256 steps per unit radius is far finer than any kernel.
    double r = filter.radius(), s1 = 0.0, s2 = 0.0;
    int n = std::max(64, int(512 * r));
    for (int i = 0; i < n; ++i) {
        double x = -r + (i + 0.5) * 2.0 * r / n, w = filter.eval(float(x));
        s1 += w, s2 += w * w;
    }
    double dx = 2.0 * r / n;
    double oneD = (s2 * dx) / ((s1 * dx) * (s1 * dx));
    return oneD * oneD;
}

std::vector<float> relativeSquaredError(const Image& image, const Image& reference) {
    checkComparable(image, reference);
    std::vector<float> e(std::size_t(image.width) * image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            double sum = 0.0;
            for (int c = 0; c < 3; ++c) {
                double d = image.at(x, y, c) - reference.at(x, y, c), r = reference.at(x, y, c);
                sum += d * d / (r * r + RelMSEEpsilon);
            }
            e[std::size_t(y) * image.width + x] = float(sum / 3.0);
        }
    return e;
}

} // namespace effigi
