#pragma once
// Vector math is GLM; these names read like the book (pbrt's Point3f, Vector3f).
// Points, vectors and normals share one type: GLM does not distinguish them, and the
// transforms below say which rule they apply.
#ifndef GLM_FORCE_XYZW_ONLY
#define GLM_FORCE_XYZW_ONLY  // also set for every target by CMake, so all TUs agree
#endif
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace effigi {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "meshes hand packed float3 arrays to Embree");

using Vector2f = glm::vec2;
using Point2f = glm::vec2;
using Vector3f = glm::vec3;
using Point3f = glm::vec3;
using Normal3f = glm::vec3;
using Vector2i = glm::ivec2;
using Point2i = glm::ivec2;
using Vector3d = glm::dvec3;

inline constexpr float Pi = std::numbers::pi_v<float>;
inline constexpr float InvPi = 1.0f / Pi;
inline constexpr float Inv2Pi = 0.5f / Pi;
inline constexpr float Inv4Pi = 0.25f / Pi;
inline constexpr float Infinity = std::numeric_limits<float>::infinity();
/// Largest float below one: [0,1) samples are clamped here.
inline constexpr float OneMinusEpsilon = 0x1.fffffep-1f;

using glm::cross;
using glm::dot;
using glm::length;
using glm::normalize;

inline float absDot(const Vector3f& a, const Vector3f& b) { return std::abs(dot(a, b)); }
inline float lengthSquared(const Vector3f& v) { return dot(v, v); }
inline float maxComponent(const Vector3f& v) { return std::max({v.x, v.y, v.z}); }
inline float maxAbsComponent(const Vector3f& v) {
    return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}
inline bool isFinite(const Vector3f& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
/// Flip n to lie in the hemisphere of v.
inline Vector3f faceForward(const Vector3f& n, const Vector3f& v) { return dot(n, v) < 0.f ? -n : n; }

inline float safeSqrt(float x) { return std::sqrt(std::max(0.f, x)); }
inline float safeAcos(float x) { return std::acos(std::clamp(x, -1.f, 1.f)); }
inline float sqr(float x) { return x * x; }
inline float lerp(float t, float a, float b) { return (1 - t) * a + t * b; }
inline float degToRad(float deg) { return deg * (Pi / 180.f); }

} // namespace effigi
