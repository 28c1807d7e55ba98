#pragma once
// Pieces shared by the texture components: Mitsuba's `to_uv` transform, and RGB texels
// stored as spectral upsampling coefficients (effigi/spectral/spectral_texel.hpp).
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/spectral/spectral_texel.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

/// The affine 2D map Mitsuba applies to texture coordinates (`to_uv`). A 4x4 transform
/// written in XML keeps its x/y rows and columns and its translation, as Mitsuba's
/// Transform4f -> Transform3f extraction does.
struct UVTransform {
    float m00 = 1.f, m01 = 0.f, m10 = 0.f, m11 = 1.f, tx = 0.f, ty = 0.f;

    static UVTransform read(const Properties& p, const std::string& name) {
        UVTransform t;
        if (!p.has(name)) return t;
        const glm::mat4 m = p.getTransform(name).matrix();  // column-major: m[col][row]
        t.m00 = m[0][0], t.m01 = m[1][0], t.tx = m[3][0];
        t.m10 = m[0][1], t.m11 = m[1][1], t.ty = m[3][1];
        if (!(std::isfinite(t.m00) && std::isfinite(t.m01) && std::isfinite(t.m10) && std::isfinite(t.m11) &&
              std::isfinite(t.tx) && std::isfinite(t.ty)))
            failAt(p.whereOf(name), "{}: '{}' is not finite", p.describe(), name);
        return t;
    }

    Point2f apply(const Point2f& uv) const { return {m00 * uv.x + m01 * uv.y + tx, m10 * uv.x + m11 * uv.y + ty}; }
    /// Chain rule for a gradient taken in transformed coordinates: Jᵀ g.
    Vector2f pullBack(const Vector2f& g) const { return {m00 * g.x + m10 * g.y, m01 * g.x + m11 * g.y}; }
};

} // namespace effigi
