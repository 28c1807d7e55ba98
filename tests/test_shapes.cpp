// Shape geometry and intersection: the mesh shapes (rectangle, cube) and mesh
// validation, the analytic shapes (sphere, disk) against analytic answers at several
// scales, nested emitters, and rays leaving a surface not hitting it again.
#include "shape_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

using namespace effigi;
using namespace effigi::test;

// ---- rectangle and cube ---------------------------------------------------------------

TEST_CASE("rectangle: geometry, winding, transforms, flip_normals", "[shapes]") {
    Ref<IShape> r = makeShape("rectangle");
    const TriangleMesh& m = *r->mesh();
    CHECK(r->area() == Approx(4.f));
    CHECK(m.triangleCount() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        CHECK(normalize(cross(p1 - p0, p2 - p0)).z == Approx(1.f));
    }
    for (std::size_t v = 0; v < 4; ++v)
        CHECK(m.uvs[v] == Point2f((m.positions[v].x + 1.f) / 2.f, (m.positions[v].y + 1.f) / 2.f));

    // Hit reconstruction from barycentrics: point, normals, uv, frame along dp/du.
    Ray ray{{0.5f, -0.25f, 3.f}, {0.f, 0.f, -2.f}};
    Hit hit;
    REQUIRE(intersectMesh(m, ray, hit));
    SurfaceInteraction si = r->interaction(ray, hit);
    CHECK(si.p.x == Approx(0.5f));
    CHECK(si.p.y == Approx(-0.25f));
    CHECK(si.p.z == Approx(0.f).margin(1e-6));
    CHECK(si.t == Approx(1.5f));
    CHECK(si.n == Normal3f(0.f, 0.f, 1.f));
    CHECK(si.uv.x == Approx(0.75f));
    CHECK(si.uv.y == Approx(0.375f));
    CHECK(si.wo.z == Approx(1.f));
    CHECK(si.shading.s.x == Approx(1.f));
    CHECK(si.shading.n.z == Approx(1.f));
    CHECK(si.shape == r.get());
    CHECK(si.bsdf != nullptr);
    CHECK(si.emitter == nullptr);

    SECTION("scaled: area") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::scale({2.f, 3.f, 1.f}));
        CHECK(makeShape("rectangle", p)->area() == Approx(24.f));
    }
    SECTION("rotated: normals follow") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::translate({1.f, 2.f, 3.f}) * Transform::rotate({1.f, 0.f, 0.f}, 90.f));
        Ref<IShape> s = makeShape("rectangle", p);
        // +z rotated by +90° about x is −y.
        for (const Normal3f& n : s->mesh()->normals) {
            CHECK(n.y == Approx(-1.f));
            CHECK(n.z == Approx(0.f).margin(1e-6));
        }
        Ray down{{1.2f, 5.f, 3.1f}, {0.f, -1.f, 0.f}};
        Hit h;
        REQUIRE(intersectMesh(*s->mesh(), down, h));
        SurfaceInteraction rs = s->interaction(down, h);
        CHECK(rs.n.y == Approx(-1.f));
        CHECK(rs.p.y == Approx(2.f));
        CHECK(rs.t == Approx(3.f));
        CHECK(s->samplePosition({0.3f, 0.6f}).n.y == Approx(-1.f));
    }
    SECTION("flat scale still has normals") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::scale({2.f, 2.f, 0.f}));
        Ref<IShape> s = makeShape("rectangle", p);
        CHECK(s->mesh()->normals[0] == Normal3f(0.f, 0.f, 1.f));
        CHECK(s->area() == Approx(16.f));
    }
    SECTION("flip_normals") {
        Properties p("shape", "rectangle");
        p.set("flip_normals", true);
        Ref<IShape> s = makeShape("rectangle", p);
        Hit h;
        REQUIRE(intersectMesh(*s->mesh(), ray, h));
        SurfaceInteraction fs = s->interaction(ray, h);
        CHECK(fs.n.z == Approx(-1.f));
        CHECK(fs.shading.n.z == Approx(-1.f));
        CHECK(fs.uv.x == Approx(0.75f));  // the parametrisation is unchanged
        CHECK(fs.uv.y == Approx(0.375f));
        CHECK(s->samplePosition({0.5f, 0.5f}).n.z == Approx(-1.f));
    }
}

TEST_CASE("rectangle: the plane's constant frame agrees with its parametrisation", "[shapes]") {
    // Rectangle shades hits with a frame computed once and samples corner + u.x e1 + u.y e2.
    // For placed rectangles (rotation, unequal scales, translation, flipped or not), two
    // hits must differ by Δuv.x dp/du + Δuv.y dp/dv, the frame must be orthonormal about
    // n = ±(dp/du × dp/dv)/|…| with s along dp/du, and a sample at u must have uv = u.
    PCG32 rng(7, 1);
    for (bool flip : {false, true}) {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::translate({0.3f, -1.f, 2.f}) * Transform::rotate({0.2f, 1.f, 0.4f}, 37.f) *
                              Transform::scale({3.f, 0.5f, 1.f}));
        p.set("flip_normals", flip);
        Ref<IShape> r = makeShape("rectangle", p);
        const PositionSample corner = r->samplePosition({0.f, 0.f});
        std::vector<SurfaceInteraction> hits;
        for (int k = 0; k < 64; ++k) {
            const Point2f u(rng.nextFloat(), rng.nextFloat());
            const PositionSample ps = r->samplePosition(u);
            CHECK(ps.uv == u);
            CHECK(ps.pdf == Approx(1.f / r->area()));
            const Vector3f off = 0.5f * ps.n + Vector3f(0.01f, 0.02f, 0.f);
            Ray ray{ps.p + off, -off};
            Hit h;
            if (!intersectMesh(*r->mesh(), ray, h)) continue;
            hits.push_back(r->interaction(ray, h));
            const SurfaceInteraction& si = hits.back();
            const Vector3f cross_ = cross(si.dpdu, si.dpdv);
            CHECK(dot(si.n, cross_ / length(cross_)) == Approx(flip ? -1.f : 1.f).margin(1e-5));
            CHECK(si.n == ps.n);
            CHECK(si.shading.n == si.n);
            CHECK(dot(si.shading.s, si.dpdu / length(si.dpdu)) == Approx(1.f).margin(1e-5));
            CHECK(dot(si.shading.s, si.shading.t) == Approx(0.f).margin(1e-6));
            CHECK(length(si.shading.t) == Approx(1.f).margin(1e-6));
            CHECK(dot(cross(si.shading.s, si.shading.t), si.shading.n) == Approx(1.f).margin(1e-5));
            const Point3f fromUV = corner.p + si.uv.x * si.dpdu + si.uv.y * si.dpdv;
            CHECK(length(fromUV - si.p) < 1e-5f * 3.f);
        }
        REQUIRE(hits.size() > 50);
        for (std::size_t k = 1; k < hits.size(); ++k) {
            const Vector2f duv = hits[k].uv - hits[0].uv;
            CHECK(length(hits[k].p - hits[0].p - (duv.x * hits[0].dpdu + duv.y * hits[0].dpdv)) < 1e-5f * 3.f);
        }
    }
    // A projective to_world leaves no parallelogram: sampled and shaded as the mesh.
    Properties p("shape", "rectangle");
    p.set("to_world", Transform::perspective(60.f, 0.1f, 10.f) * Transform::translate({0.f, 0.f, 3.f}) *
                          Transform::rotate({1.f, 0.f, 0.f}, 50.f));
    Ref<IShape> q = makeShape("rectangle", p);
    for (float v : {0.1f, 0.5f, 0.9f}) {
        const PositionSample ps = q->samplePosition({0.5f, v});
        CHECK(length(ps.n) == Approx(1.f));
        CHECK(ps.pdf == Approx(1.f / q->area()));
    }
}

TEST_CASE("rectangle: solid-angle samples keep a finite density at tiny and huge scales", "[shapes]") {
    // p_ω = p_A d² / |cos θ_light| (IShape::sampleDirection) for small lights seen from
    // far away and large ones from close by, against the same formula in double. A small
    // light 1e12 away has p_ω near 1e30: forming d² · dist first would overflow there.
    for (float size : {1e-3f, 1.f, 1e3f})
        for (float dist : {1e-3f, 1.f, 1e6f, 1e12f}) {
            Properties p("shape", "rectangle");
            p.set("to_world", Transform::scale({size, size, size}));
            Ref<IShape> r = makeShape("rectangle", p);
            const Point3f ref = dist * Point3f(0.3f, 0.2f, 1.f);
            for (const Point2f u : {Point2f(0.5f, 0.5f), Point2f(0.1f, 0.9f), Point2f(0.99f, 0.02f)}) {
                const DirectionSample ds = r->sampleDirection(ref, u);
                const glm::dvec3 d = glm::dvec3(ds.p) - glm::dvec3(ref);
                const double d2 = glm::dot(d, d), cosLight = std::abs(d.z) / std::sqrt(d2);
                const double expected = d2 / (double(r->area()) * cosLight);
                INFO("size " << size << " distance " << dist << ": pdf " << ds.pdf << ", expected " << expected);
                CHECK(std::isfinite(ds.pdf));
                CHECK(double(ds.pdf) == Approx(expected).epsilon(1e-4));
                CHECK(double(ds.dist) == Approx(std::sqrt(d2)).epsilon(1e-5));
            }
        }
}

TEST_CASE("cube: 24 vertices, outward winding and normals, face_normals", "[shapes]") {
    Ref<IShape> c = makeShape("cube");
    const TriangleMesh& m = *c->mesh();
    CHECK(m.vertexCount() == 24);
    CHECK(m.triangleCount() == 12);
    CHECK(c->area() == Approx(24.f));
    for (std::size_t i = 0; i < 12; ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        Vector3f n = normalize(cross(p1 - p0, p2 - p0));
        Point3f centroid = (p0 + p1 + p2) / 3.f;
        CHECK(maxAbsComponent(n) == Approx(1.f));
        CHECK(dot(n, centroid) > 0.5f);  // outward
        for (int k = 0; k < 3; ++k) CHECK(dot(m.normals[m.indices[3 * i + k]], n) == Approx(1.f));
    }
    Properties p("shape", "cube");
    p.set("face_normals", true);
    p.set("to_world", Transform::scale({1.f, 2.f, 3.f}));
    Ref<IShape> fc = makeShape("cube", p);
    CHECK(fc->mesh()->normals.empty());
    CHECK(fc->area() == Approx(8.f * (2.f + 6.f + 3.f)));
}

TEST_CASE("mesh validation: errors name the source", "[shapes]") {
    TriangleMesh m;
    m.positions = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
    m.indices = {0, 1, 3};
    requireThrowsNaming([&] { m.validate("bad.mesh"); }, "bad.mesh");
    m.indices = {0, 1, 2};
    m.positions[1].x = std::numeric_limits<float>::quiet_NaN();
    requireThrowsNaming([&] { m.validate("nan.mesh"); }, "nan.mesh");
    m.positions[1].x = 1.f;
    m.uvs.resize(2);
    requireThrowsNaming([&] { m.validate("uv.mesh"); }, "uv.mesh");
}

// ---- sphere and disk ------------------------------------------------------------------

TEST_CASE("sphere: intersection against analytic answers", "[shapes][sphere]") {
    for (float radius : {1e-4f, 1.f, 1e4f}) {
        INFO("radius " << radius);
        Properties p("shape", "sphere");
        p.set("radius", double(radius));
        p.set("center", PointValue{{0.f, 0.f, 0.f}});
        Ref<IShape> s = makeShape("sphere", p);
        CHECK(s->area() == Approx(4.f * Pi * radius * radius));
        float t;
        Point2f uv;
        const float R = radius;

        // From outside, head on; unnormalised direction halves t.
        REQUIRE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(4.f * R).epsilon(1e-6));
        REQUIRE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 2.f}}, t, uv));
        CHECK(t == Approx(2.f * R).epsilon(1e-6));
        // Off-axis: t = 5R − sqrt(R² − x0²).
        REQUIRE(s->intersect(Ray{{0.6f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(4.2f * R).epsilon(1e-6));
        // From inside: the far side.
        REQUIRE(s->intersect(Ray{{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}}, t, uv));
        CHECK(t == Approx(R).epsilon(1e-6));
        REQUIRE(s->intersect(Ray{{0.f, 0.5f * R, 0.f}, {0.f, 1.f, 0.f}}, t, uv));
        CHECK(t == Approx(0.5f * R).epsilon(1e-6));
        // Misses: pointing away, beyond tMax, passing by.
        CHECK_FALSE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK_FALSE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 1.f}, 3.9f * R}, t, uv));
        CHECK_FALSE(s->intersect(Ray{{1.001f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        // Grazing: just inside the silhouette hits near the tangent point, just outside misses.
        REQUIRE(s->intersect(Ray{{0.9999f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(5.f * R).epsilon(0.02));
        // Tangent exactly: if reported, the hit is the tangent point.
        if (s->intersect(Ray{{R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv)) CHECK(t == Approx(5.f * R).epsilon(1e-3));

        // Interaction: on the surface, outward normal, uv in range.
        Ray ray{{0.3f * R, -0.2f * R, -5.f * R}, {0.f, 0.f, 1.f}};
        REQUIRE(s->intersect(ray, t, uv));
        SurfaceInteraction si = s->interaction(ray, Hit{t, 0, 0, uv});
        CHECK(length(si.p) == Approx(R).epsilon(1e-6));
        CHECK(dot(si.n, si.p / R) == Approx(1.f));
        CHECK(si.uv.x >= 0.f);
        CHECK(si.uv.x < 1.f);
        CHECK(si.uv.y == Approx(safeAcos(si.p.z / R) * InvPi).epsilon(1e-4));
        CHECK(dot(si.shading.s, si.shading.n) == Approx(0.f).margin(1e-5));
        CHECK(length(cross(si.shading.s, Vector3f(-si.p.y, si.p.x, 0.f))) == Approx(0.f).margin(1e-3 * R));
    }
}

TEST_CASE("sphere: center, to_world, flip_normals, errors", "[shapes][sphere]") {
    Properties p("shape", "sphere");
    p.set("center", PointValue{{1.f, 0.f, 0.f}});
    p.set("radius", 0.5);
    p.set("to_world", Transform::translate({0.f, 2.f, 0.f}) * Transform::scale(Vector3f(3.f)));
    p.set("flip_normals", true);
    Ref<IShape> s = makeShape("sphere", p);
    // Center (3, 2, 0), radius 1.5.
    CHECK(s->bbox().min.x == Approx(1.5f));
    CHECK(s->bbox().max.y == Approx(3.5f));
    CHECK(s->area() == Approx(4.f * Pi * 2.25f));
    float t;
    Point2f uv;
    Ray ray{{3.f, 2.f, -10.f}, {0.f, 0.f, 1.f}};
    REQUIRE(s->intersect(ray, t, uv));
    CHECK(t == Approx(8.5f));
    SurfaceInteraction si = s->interaction(ray, Hit{t, 0, 0, uv});
    CHECK(si.n.z == Approx(1.f));  // flipped: inward at the bottom of the sphere
    CHECK(si.shading.n.z == Approx(1.f));

    Properties bad("shape", "sphere");
    bad.set("to_world", Transform::scale({1.f, 2.f, 1.f}));
    requireThrowsNaming([&] { makeShape("sphere", bad); }, "to_world");
    Properties zero("shape", "sphere");
    zero.set("radius", 0.0);
    requireThrowsNaming([&] { makeShape("sphere", zero); }, "radius");
}

TEST_CASE("disk: intersection against analytic answers", "[shapes][disk]") {
    for (float scale : {1e-4f, 1.f, 1e4f}) {
        INFO("scale " << scale);
        Properties p("shape", "disk");
        p.set("to_world", Transform::translate({0.f, 0.f, scale}) * Transform::scale(Vector3f(scale)));
        Ref<IShape> d = makeShape("disk", p);
        const float S = scale;
        CHECK(d->area() == Approx(Pi * S * S));
        float t;
        Point2f uv;
        // From above and from below (both sides are hit).
        REQUIRE(d->intersect(Ray{{0.5f * S, 0.f, 3.f * S}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK(t == Approx(2.f * S).epsilon(1e-6));
        CHECK(uv.x == Approx(0.5f));
        REQUIRE(d->intersect(Ray{{0.f, -0.5f * S, -S}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(2.f * S).epsilon(1e-6));
        CHECK(uv.y == Approx(0.75f));
        // Outside the radius, parallel, pointing away, beyond tMax.
        CHECK_FALSE(d->intersect(Ray{{0.8f * S, 0.8f * S, 3.f * S}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{-3.f * S, 0.f, S}, {1.f, 0.f, 0.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{0.f, 0.f, 3.f * S}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{0.f, 0.f, 3.f * S}, {0.f, 0.f, -1.f}, 1.9f * S}, t, uv));
        // Oblique.
        Ray ob{{-S, 0.f, 2.f * S}, {1.f, 0.f, -1.f}};
        REQUIRE(d->intersect(ob, t, uv));
        CHECK(t == Approx(S).epsilon(1e-6));
        SurfaceInteraction si = d->interaction(ob, Hit{t, 0, 0, uv});
        CHECK(si.p.z == Approx(S).epsilon(1e-6));
        CHECK(si.p.x == Approx(0.f).margin(1e-6 * S));
        CHECK(si.n.z == Approx(1.f));
        CHECK(si.wo.x == Approx(-std::sqrt(0.5f)));
    }
    Properties e("shape", "disk");
    e.set("to_world", Transform::rotate({0.f, 1.f, 0.f}, 90.f) * Transform::scale({2.f, 0.5f, 1.f}));
    e.set("flip_normals", true);
    Ref<IShape> ellipse = makeShape("disk", e);
    CHECK(ellipse->area() == Approx(Pi));
    CHECK(ellipse->samplePosition({0.2f, 0.7f}).n.x == Approx(-1.f));  // +z -> +x, flipped
    CHECK(ellipse->bbox().max.z == Approx(2.f));
    CHECK(ellipse->bbox().max.y == Approx(0.5f));
}

// ---- nested emitters and self-intersection ---------------------------------------------

TEST_CASE("shapes carry their nested emitter, attach errors point at the scene", "[shapes]") {
    Properties ep("emitter", "area");
    Ref<IComponent> area = Registry::instance().create("emitter", "area", ep);
    Properties p("shape", "sphere");
    p.set("emitter", ComponentValue{"emitter", area});
    Ref<IShape> s = makeShape("sphere", p);
    REQUIRE(s->emitter() != nullptr);
    CHECK(s->emitter() == query<IEmitter>(area).get());
    Ray ray{{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}};
    Hit hit;
    REQUIRE(trace(*s, ray, hit));
    CHECK(s->interaction(ray, hit).emitter == s->emitter());

    // A point light cannot be nested in a shape: the error names where it was written.
    Properties pp("emitter", "point");
    Ref<IComponent> point = Registry::instance().create("emitter", "point", pp);
    Properties q("shape", "rectangle");
    q.set("emitter", ComponentValue{"emitter", point}, SourceLocation{"scene.xml", 12});
    requireThrowsNaming([&] { makeShape("rectangle", q); }, "scene.xml:12");
}

TEST_CASE("analytic shapes: rays leaving the surface do not hit it again", "[shapes][sphere][disk]") {
    PCG32 rng(31, 37);
    for (float scale : {1e-4f, 1.f, 1e4f}) {
        INFO("scale " << scale);
        Properties sp("shape", "sphere");
        sp.set("radius", double(scale));
        sp.set("center", PointValue{{0.3f * scale, -0.2f * scale, 0.1f * scale}});
        Properties dp("shape", "disk");
        dp.set("to_world", Transform::translate(Vector3f(0.5f * scale)) * Transform::scale(Vector3f(scale)));
        for (bool isSphere : {true, false}) {
            Ref<IShape> s = isSphere ? makeShape("sphere", sp) : makeShape("disk", dp);
            int selfHits = 0, wrongFar = 0;
            std::string detail;
            for (int i = 0; i < 2000; ++i) {
                PositionSample ps = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
                Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
                SurfaceInteraction si;
                si.p = ps.p;
                si.n = ps.n;
                Ray ray = si.spawnRay(d);
                float t;
                Point2f uv;
                bool hit = s->intersect(ray, t, uv);
                if (dot(d, ps.n) > 0.f || !isSphere) {
                    // Outward from a convex surface (or off a plane): nothing to hit.
                    selfHits += hit;
                } else {
                    // Inward through a sphere: the far side, from the (offset) ray origin.
                    Vector3d oc = Vector3d(ray.o) - Vector3d(0.3, -0.2, 0.1) * double(scale), dd(d);
                    double b = glm::dot(oc, dd), c = glm::dot(oc, oc) - double(scale) * double(scale);
                    double far = -b + std::sqrt(std::max(0.0, b * b - c));
                    if (!hit || std::abs(double(t) - far) > 1e-5 * double(scale)) {
                        ++wrongFar;
                        detail += fmt::format(" [hit {} t {} expected {}]", hit, t, far);
                    }
                }
            }
            INFO(detail);
            CHECK(selfHits == 0);
            CHECK(wrongFar == 0);
        }
    }
}
