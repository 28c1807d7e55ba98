#pragma once
// Helpers shared by the "warps in use" tests (test_warps_in_use, test_warps_in_use_bsdf,
// test_warps_in_use_lights): warp components by name, bit-for-bit comparison, an
// emitter's host square, the error of a one-element scene, and two warps defined here the
// way a plugin would define them, so that a nested warp with a density unlike any
// built-in one can be checked.
#include "xml_helpers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <string>

namespace effigi::test {

inline Ref<IWarp> makeWarp(const std::string& type) {
    Properties p("warp", type);
    Ref<IWarp> w = query<IWarp>(Registry::instance().create("warp", type, p));
    REQUIRE(w);
    return w;
}

inline PropertyValue warpValue(const std::string& type) { return ComponentValue{"warp", makeWarp(type)}; }
inline PropertyValue warpValue(const Ref<IWarp>& w) { return ComponentValue{"warp", w}; }

inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool sameBits(const Vector3f& a, const Vector3f& b) {
    return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}

/// A unit square [-½,½]² at z = 0, normal +z, carrying the emitter.
inline Ref<IShape> square(const Ref<IEmitter>& e) {
    Properties p("shape", "rectangle");
    p.set("to_world", Transform::scale(Vector3f(0.5f, 0.5f, 1.f)));
    p.set("emitter", ComponentValue{"emitter", e});
    Ref<IShape> s = query<IShape>(Registry::instance().create("shape", "rectangle", p));
    REQUIRE(s);
    e->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
    return s;
}

/// The error of loading a scene "bad.xml" whose line 3 is `inner`, inside `open` (line 2).
inline std::string nestedWarpError(const std::string& open, const std::string& close, const std::string& inner) {
    const std::string text = "<scene version=\"3.0.0\">\n  " + open + "\n    " + inner + "\n  " + close + "\n</scene>\n";
    return errorOf([&] { loadScene(*xml::parseString(text, "bad.xml", {})); });
}

/// Directions on the whole sphere with density (1 + z/2)/(4π): z = −2 + √(1 + 8 u1) inverts
/// the CDF of (1 + z/2)/2 on [−1, 1], φ = 2π u2. Bounded away from 0, unlike any built-in
/// warp's on the sphere, so a density mistaken for uniform shows as a bias.
class TiltedSphereWarp final : public Implements<IWarp> {
public:
    WarpDomain domain() const override { return {WarpDomain::Kind::Sphere, {}, {}, "sphere, density (1 + z/2)/(4π)"}; }
    Vector3f sample(const Point2f& u) const override {
        float z = std::clamp(-2.f + std::sqrt(1.f + 8.f * u.x), -1.f, 1.f);
        float r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * Pi * u.y;
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    float pdf(const Vector3f& v) const override { return (1.f + 0.5f * v.z) * Inv4Pi; }
};

/// Points of the unit disk by the polar map r = u1, φ = 2π u2: density 1/(2π r), not
/// uniform; bounds [−1, 1]² (it covers the disk).
class PolarDiskWarp final : public Implements<IWarp> {
public:
    WarpDomain domain() const override { return {WarpDomain::Kind::Plane, Point2f(-1.f), Point2f(1.f), "polar disk"}; }
    Vector3f sample(const Point2f& u) const override {
        float phi = 2.f * Pi * u.y;
        return {u.x * std::cos(phi), u.x * std::sin(phi), 0.f};
    }
    float pdf(const Vector3f& p) const override {
        float r = std::sqrt(p.x * p.x + p.y * p.y);
        return r > 0.f && r <= 1.f ? Inv2Pi / r : 0.f;
    }
};

} // namespace effigi::test
