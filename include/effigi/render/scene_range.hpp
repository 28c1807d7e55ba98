#pragma once
// The coordinate range a scene must fit in, and the load-time checks that keep every ray
// an accelerator sees valid and every render scale-invariant.
//
// Embree (3.13, kernels/common/ray.h) accepts only rays whose origin and direction lie
// within ±FLT_LARGE = 1.844e18 per axis, and asserts otherwise: a shape translated to
// x = 1e38 is finite, but a ray leaving it is not a valid Embree ray (issue 12). Long
// before that, float arithmetic that is cubic or quartic in lengths overflows and an
// image silently goes wrong: the ray/triangle test's distance term (Woop et al.'s T,
// Embree's Plücker test) grows like |p − o|³ and overflows near 7e12, so triangles
// vanish; a radiosity patch's area squares a product of two edge lengths and overflows
// near 1e10, so the room goes black. Measured: scenes scaled by 1e9 render the
// unit-scale image with path, direct, ptracer, radiosity and twopass; scaled by 1e10,
// radiosity and twopass render black, by 1e12 triangles vanish for every accelerator.
// Hence ±1e9 scene units (a million kilometres in metres; tests/test_robustness.cpp
// renders a scene that reaches 0.975e9).
// Rays then start within (1 + √6)·1e9 per axis (the emitters at infinity start theirs
// on a disk behind the bounding sphere, SceneSphere::parallelRay).
#include "effigi/math/bbox.hpp"

#include <string>

namespace effigi {

class ICamera;
class IShape;

/// Largest magnitude of any scene coordinate (shape bounds, camera and light positions).
inline constexpr float MaxSceneCoordinate = 1e9f;

/// Whether every coordinate of p is finite and within ±MaxSceneCoordinate.
bool inSceneRange(const Point3f& p);

/// Empty when the shape's bounds are finite and within range; otherwise why not, as a
/// phrase for an error message ("its bounds reach x = 1e+38, beyond ...").
std::string shapeRangeProblem(const IShape& shape);

/// Empty when the rays the camera generates (film corners and centre, lens corners) start
/// within range and are finite; otherwise why not.
std::string cameraRangeProblem(const ICamera& camera);

} // namespace effigi
