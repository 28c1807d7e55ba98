#pragma once
// An orthonormal frame (s, t, n). Shading happens in the local frame where n = +z.
#include "effigi/math/vector.hpp"

namespace effigi {

/// Orthonormal basis from a unit vector without branches on near-parallel axes
/// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
inline void coordinateSystem(const Vector3f& n, Vector3f& s, Vector3f& t) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    s = Vector3f(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vector3f(b, sign + n.y * n.y * a, -n.y);
}

struct Frame {
    Vector3f s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    Frame() = default;
    explicit Frame(const Vector3f& normal) : n(normal) { coordinateSystem(n, s, t); }
    Frame(const Vector3f& s_, const Vector3f& t_, const Vector3f& n_) : s(s_), t(t_), n(n_) {}

    Vector3f toLocal(const Vector3f& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vector3f toWorld(const Vector3f& v) const { return s * v.x + t * v.y + n * v.z; }

    // Trigonometry of a direction in the local frame (pbrt's CosTheta & co.).
    static float cosTheta(const Vector3f& v) { return v.z; }
    static float cos2Theta(const Vector3f& v) { return v.z * v.z; }
    static float absCosTheta(const Vector3f& v) { return std::abs(v.z); }
    static float sin2Theta(const Vector3f& v) { return std::max(0.f, 1.f - v.z * v.z); }
    static float sinTheta(const Vector3f& v) { return std::sqrt(sin2Theta(v)); }
    static float tanTheta(const Vector3f& v) { return sinTheta(v) / cosTheta(v); }
    static bool sameHemisphere(const Vector3f& a, const Vector3f& b) { return a.z * b.z > 0; }
};

} // namespace effigi
