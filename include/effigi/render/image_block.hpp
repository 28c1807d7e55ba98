#pragma once
// A rectangle of film pixels that one thread accumulates filtered samples into before
// it is merged into the film (Mitsuba's ImageBlock). Each pixel holds N channels and
// the filter-weight sum; the block has a border wide enough for the filter's support.
//
// Coordinates: pixel (i, j) covers [i, i+1) × [j, j+1) and has its centre at
// (i + 0.5, j + 0.5). A block covers the pixels [offset, offset + size) in the same
// frame as the positions passed to put(); for a film that is the crop window's frame
// (see IFilm::cropOffset()).
#include "effigi/math/vector.hpp"

#include <vector>

namespace effigi {

class IFilter;

/// A reconstruction filter tabulated once, so splatting costs no virtual calls.
/// Resolution entries per pixel of radius, sampled at the bin edges |x| = k / Resolution
/// and interpolated linearly: nearest-bin lookup would be biased by half a bin's slope
/// at lattice-aligned positions (pixel centres, stratified samples), ~1.5 % per axis
/// for the default Gaussian; interpolation brings the error below 1e-4.
/// |x| = radius still weighs (a 0.5-radius box weighs a sample on a pixel edge);
/// beyond the radius, or NaN, the weight is 0.
class FilterTable {
public:
    FilterTable() = default;
    explicit FilterTable(const IFilter& f);
    float radius() const { return m_radius; }
    float operator()(float x) const {
        float ax = std::abs(x) * m_scale;
        if (!(ax <= m_end)) return 0.f;  // beyond the support, or NaN
        int i = static_cast<int>(ax);
        i = i < m_last ? i : m_last;
        float t = ax - float(i);
        return m_values[i] + t * (m_values[i + 1] - m_values[i]);
    }

    static constexpr int Resolution = 64;  // entries per unit of radius (per pixel)

private:
    float m_radius = 0.5f, m_scale = 0.f, m_end = -1.f;
    int m_last = 0;                // index of the last interval (entries - 2)
    std::vector<float> m_values;   // eval(k / scale), k = 0 .. entries - 1
};

class ImageBlock {
public:
    ImageBlock() = default;
    /// A zeroed block for pixels [offset, offset + size) with `channels` values each.
    /// The filter table must outlive the block (films own theirs).
    ImageBlock(Point2i offset, Vector2i size, int channels, const FilterTable* filter);

    Point2i offset() const { return m_offset; }
    Vector2i size() const { return m_size; }
    /// Extra pixels stored on each side: ceil(radius − 0.5), 0 for the 0.5-radius box.
    int border() const { return m_border; }
    int channels() const { return m_channels; }
    /// Floats per pixel: channels + weight.
    int stride() const { return m_channels + 1; }
    /// Width and height of the stored rectangle (size + 2 border).
    Vector2i storageSize() const { return m_size + 2 * m_border; }

    void clear();
    /// Splat a sample at continuous position pos (pixel centres at i + 0.5): every
    /// stored pixel whose centre lies within the filter radius in x and y gets
    /// values · w and w, w = filter(cx − pos.x) · filter(cy − pos.y). No allocation.
    void put(const Point2f& pos, const float* values);
    /// Pixel storage including the border; row-major, storageSize().x wide, stride()
    /// floats per pixel with the weight last.
    const std::vector<float>& data() const { return m_data; }
    std::vector<float>& data() { return m_data; }
    /// The stored floats of pixel (x, y) given in block-frame coordinates; the pixel must
    /// lie in [offset − border, offset + size + border).
    const float* pixel(int x, int y) const {
        Vector2i s = storageSize();
        return m_data.data() + (std::size_t(y - m_offset.y + m_border) * s.x + (x - m_offset.x + m_border)) * stride();
    }

private:
    Point2i m_offset{0};
    Vector2i m_size{0};
    int m_border = 0, m_channels = 0;
    const FilterTable* m_filter = nullptr;
    std::vector<float> m_data;
};

} // namespace effigi
