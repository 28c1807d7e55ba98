#pragma once
// Splatting a contribution that lands anywhere on the film (light tracing: ptracer, and
// bdpt's t = 1 strategies). The sample is spread over the reconstruction filter with
// weights normalised to sum to 1 (Mitsuba's normalised image block), so the filter only
// blurs and never changes the brightness; the caller scales the summed splats by the
// number of light paths per pixel (see ptracer.cpp for the normalisation).
#include "effigi/render/image_block.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

#include <cmath>

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
        if (!isFinite(xyz)) {
            ++ts.rejected;
            return;
        }
        Point2f pos = pFilm - Point2f(m_offset);
        float norm = footprint(pos.x) * footprint(pos.y);
        if (!(norm > 0.f)) return;
        xyz /= norm;
        block.put(pos, &xyz.x);
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
