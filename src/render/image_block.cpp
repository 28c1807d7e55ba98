// FilterTable and ImageBlock: the per-thread splatting buffer behind every film.
#include "effigi/render/image_block.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <algorithm>
#include <cmath>

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

    // Column weights once per sample (the filter is separable); a stack buffer covers
    // every practical radius, wider kernels look the table up per pixel.
    constexpr int MaxCached = 64;
    float wxCache[MaxCached];
    const int nx = xhi - xlo + 1;
    const bool cached = nx <= MaxCached;
    if (cached)
        for (int i = 0; i < nx; ++i) wxCache[i] = filter(float(xlo + i) + 0.5f - pos.x);

    const int n = stride();
    for (int y = ylo; y <= yhi; ++y) {
        const float wy = filter(float(y) + 0.5f - pos.y);
        if (wy == 0.f) continue;
        float* row = m_data.data() + (std::size_t(y - y0) * s.x + std::size_t(xlo - x0)) * n;
        for (int i = 0; i < nx; ++i, row += n) {
            const float wx = cached ? wxCache[i] : filter(float(xlo + i) + 0.5f - pos.x);
            const float w = wy * wx;
            if (w == 0.f) continue;
            for (int c = 0; c < m_channels; ++c) row[c] += values[c] * w;
            row[m_channels] += w;
        }
    }
}

} // namespace effigi
