// FilterTable and ImageBlock: the per-thread splatting buffer behind every film.
#include "effigi/render/image_block.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace effigi {

FilterTable::FilterTable(const IFilter& f) : m_radius(f.radius()) {
    if (!(m_radius > 0.f) || !std::isfinite(m_radius) || m_radius > 1024.f)
        fail("reconstruction filter {}: radius {} is not in (0, 1024]", f.typeName(), m_radius);
    const int n = std::max(1, int(std::ceil(float(Resolution) * m_radius)));  // intervals
    m_values.resize(std::size_t(n) + 1);
    m_scale = float(n) / m_radius;
    m_end = float(n);
    m_last = n - 1;
    for (int k = 0; k <= n; ++k) m_values[std::size_t(k)] = f.eval(float(k) / m_scale);
    // The radius itself is inside the support (|x| <= radius), whatever rounding did.
    m_values[std::size_t(n)] = f.eval(m_radius);
}

ImageBlock::ImageBlock(Point2i offset, Vector2i size, int channels, const FilterTable* filter)
    : m_offset(offset), m_size(size), m_channels(channels), m_filter(filter) {
    if (size.x < 0 || size.y < 0 || channels < 0)
        fail("image block: invalid size {}x{} or channel count {}", size.x, size.y, channels);
    if (!filter) fail("image block: no reconstruction filter");
    // A pixel is touched when its centre is within the radius of the sample; samples
    // inside [offset, offset + size) reach at most ceil(radius − 0.5) pixels beyond.
    m_border = std::max(0, int(std::ceil(filter->radius() - 0.5f)));
    Vector2i s = storageSize();
    m_data.assign(std::size_t(s.x) * std::size_t(s.y) * std::size_t(stride()), 0.f);
}

namespace {
/// One pixel's channels and weight += the sample's values with filter weight w.
void addWeighted(float* pixel, const float* values, int channels, float w) {
    if (w == 0.f) return;
    for (int c = 0; c < channels; ++c) pixel[c] += values[c] * w;
    pixel[channels] += w;
}
} // namespace

void ImageBlock::clear() { std::fill(m_data.begin(), m_data.end(), 0.f); }

void ImageBlock::put(const Point2f& pos, const float* values) {
    if (!m_filter) return;
    const FilterTable& filter = *m_filter;
    const float r = filter.radius();
    // The stored rectangle, in the block's frame.
    const int x0 = m_offset.x - m_border, y0 = m_offset.y - m_border;
    const Vector2i s = storageSize();
    // Reject positions whose support misses the block (and NaN) before converting to
    // int, so no float -> int conversion can overflow.
    const float margin = r + 1.f;
    if (!(pos.x >= float(x0) - margin && pos.x <= float(x0 + s.x) + margin &&
          pos.y >= float(y0) - margin && pos.y <= float(y0 + s.y) + margin))
        return;
    // Pixels with pos − r < i + 0.5 <= pos + r. The half-open side makes a 0.5-radius
    // box touch exactly the pixel [i, i+1) that contains pos.
    int xlo = int(std::floor(pos.x - r - 0.5f)) + 1, xhi = int(std::floor(pos.x + r - 0.5f));
    int ylo = int(std::floor(pos.y - r - 0.5f)) + 1, yhi = int(std::floor(pos.y + r - 0.5f));
    xlo = std::max(xlo, x0);
    ylo = std::max(ylo, y0);
    xhi = std::min(xhi, x0 + s.x - 1);
    yhi = std::min(yhi, y0 + s.y - 1);
    if (xlo > xhi || ylo > yhi) return;

    // Column and row weights once per sample (the filter is separable); a stack buffer
    // covers every practical radius, wider kernels look the table up per pixel.
    constexpr int MaxCached = 64;
    float wx[MaxCached], wy[MaxCached];
    const int nx = xhi - xlo + 1, ny = yhi - ylo + 1;
    const int n = stride();
    if (nx > MaxCached || ny > MaxCached) {
        for (int y = ylo; y <= yhi; ++y) {
            const float wy = filter(float(y) + 0.5f - pos.y);
            if (wy == 0.f) continue;
            float* row = m_data.data() + (std::size_t(y - y0) * s.x + std::size_t(xlo - x0)) * n;
            for (int x = xlo; x <= xhi; ++x, row += n)
                addWeighted(row, values, m_channels, wy * filter(float(x) + 0.5f - pos.x));
        }
        return;
    }
    for (int i = 0; i < nx; ++i) wx[i] = filter(float(xlo + i) + 0.5f - pos.x);
    for (int j = 0; j < ny; ++j) wy[j] = filter(float(ylo + j) + 0.5f - pos.y);
    if (n == 4) {
        // Three channels and the weight (XYZ films, the common case): one 4-wide
        // multiply-add per pixel, the same sums in the same order as the scalar loop.
        using V4 = float __attribute__((vector_size(16)));
        const V4 v = {values[0], values[1], values[2], 1.f};
        for (int j = 0; j < ny; ++j) {
            if (wy[j] == 0.f) continue;
            float* row = m_data.data() + (std::size_t(ylo + j - y0) * s.x + std::size_t(xlo - x0)) * 4;
            for (int i = 0; i < nx; ++i, row += 4) {
                V4 acc;
                std::memcpy(&acc, row, sizeof acc);
                acc += v * (wy[j] * wx[i]);
                std::memcpy(row, &acc, sizeof acc);
            }
        }
        return;
    }
    for (int j = 0; j < ny; ++j) {
        if (wy[j] == 0.f) continue;
        float* row = m_data.data() + (std::size_t(ylo + j - y0) * s.x + std::size_t(xlo - x0)) * n;
        for (int i = 0; i < nx; ++i, row += n) addWeighted(row, values, m_channels, wy[j] * wx[i]);
    }
}

} // namespace effigi
