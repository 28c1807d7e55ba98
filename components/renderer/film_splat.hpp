#pragma once
// Splatting a contribution that lands anywhere on the film (light tracing: ptracer, and
// bdpt's t = 1 strategies). The sample is spread over the reconstruction filter with
// weights normalised to sum to 1 (Mitsuba's normalised image block), so the filter only
// blurs and never changes the brightness; the caller scales the summed splats by the
// number of light paths per pixel (see ptracer.cpp for the normalisation).
#include "effigi/render/image_block.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace effigi {

class FilmSplatter {
public:
    /// `cropOffset`: the crop window's top-left pixel (splats arrive in full-film pixels).
    FilmSplatter(const FilterTable& filter, Point2i cropOffset) : m_filter(filter), m_offset(cropOffset) {}

    /// Put XYZ of the spectral contribution L at the full-film position pFilm; NaN/Inf
    /// contributions are counted in ts.rejected and dropped.
    void splat(const Point2f& pFilm, const SampledSpectrum& L, const SampledWavelengths& lambda, ImageBlock& block,
               TileStats& ts) const {
        Vector3f xyz = cie::toXYZ(L, lambda);
        if (block.channels() == 3) return splat(pFilm, &xyz.x, block, ts);
        thread_local std::vector<float> values;  // a block with more channels: zeros there
        values.assign(std::size_t(block.channels()), 0.f);
        std::copy(&xyz.x, &xyz.x + 3, values.begin());
        splat(pFilm, values.data(), block, ts);
    }

    /// Put all block.channels() values (X, Y, Z first) at pFilm; `values` is scaled in
    /// place by the footprint's normalisation.
    void splat(const Point2f& pFilm, float* values, ImageBlock& block, TileStats& ts) const {
        const int n = block.channels();
        for (int c = 0; c < n; ++c)
            if (!std::isfinite(values[c])) {
                ++ts.rejected;
                return;
            }
        Point2f pos = pFilm - Point2f(m_offset);
        float norm = footprint(pos.x) * footprint(pos.y);
        if (!(norm > 0.f)) return;
        for (int c = 0; c < n; ++c) values[c] /= norm;
        block.put(pos, values);
    }

private:
    /// Sum of the filter's weights over the pixel centres within its radius of x.
    float footprint(float x) const {
        float r = m_filter.radius(), sum = 0.f;
        for (int i = int(std::floor(x - r - 0.5f)); i <= int(std::ceil(x + r - 0.5f)); ++i)
            sum += m_filter(float(i) + 0.5f - x);
        return sum;
    }

    const FilterTable& m_filter;
    Point2i m_offset;
};

} // namespace effigi
