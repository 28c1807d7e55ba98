// Scenes and rays of the accelerator suite (accelerator_scenes.hpp): the ordinary scenes
// and the list of all of them. The stiff scenes are in accelerator_stiff_scenes.cpp, the
// arbiter that judges disagreements in accelerator_arbiter.cpp.
#include "conformance/accelerator_builder.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/math/rng.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace effigi::conform {

/// Random triangles of many sizes in three meshes, three spheres and a disk, all scaled
/// by s; random rays of random lengths, 30 % with a finite tMax.
void soup(Builder& b, bool quick, float s) {
    const int n = quick ? 500 : 2000;
    TriangleMesh m[3];
    for (int i = 0; i < n; ++i) {
        Point3f c = b.inBox(-1.f, 1.f);
        float size = b.logUniform(0.02f, 0.4f);
        Point3f p[3];
        for (auto& q : p) q = s * (c + size * b.rng.nextFloat() * b.direction());
        Builder::triangle(m[i % 3], p[0], p[1], p[2]);
    }
    for (auto& mesh : m) b.addMesh(std::move(mesh));
    for (int i = 0; i < 3; ++i) b.sphere(s * b.inBox(-0.8f, 0.8f), s * b.logUniform(0.05f, 0.3f));
    b.transformed("disk", Transform::translate(s * b.inBox(-0.5f, 0.5f)) * Transform::rotate(b.direction(), b.uniform(0.f, 180.f)) *
                              Transform::scale(Vector3f(s * 0.4f)));
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Vector3f d = b.direction() * b.logUniform(0.25f, 4.f);
        float tMax = b.rng.nextFloat() < 0.3f ? b.uniform(0.05f, 3.f) * s / length(d) : Infinity;
        b.ray(s * b.inBox(-1.5f, 1.5f), d, tMax);
    }
}

namespace {

/// The Cornell box of scenes/cornell-box/geometry.xml, built from the same rectangles and
/// cubes; rays from inside the box in all directions and from the camera into it.
void cornell(Builder& b, bool quick) {
    using T = Transform;
    const Vector3f X(1, 0, 0), Y(0, 1, 0);
    b.transformed("rectangle", T::translate({0, 0.99f, 0.01f}) * T::rotate(X, 90) * T::scale({0.23f, 0.19f, 0.19f}));
    b.transformed("rectangle", T::translate({0, -1, 0}) * T::rotate(X, -90));
    b.transformed("rectangle", T::translate({0, 1, 0}) * T::rotate(X, 90));
    b.transformed("rectangle", T::translate({0, 0, -1}));
    b.transformed("rectangle", T::translate({1, 0, 0}) * T::rotate(Y, -90));
    b.transformed("rectangle", T::translate({-1, 0, 0}) * T::rotate(Y, 90));
    b.transformed("cube", T::translate({0.335f, -0.7f, 0.38f}) * T::rotate(Y, -17) * T::scale(Vector3f(0.3f)));
    b.transformed("cube", T::translate({-0.33f, -0.4f, -0.28f}) * T::rotate(Y, 18.25f) * T::scale({0.3f, 0.61f, 0.3f}));
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        if (i % 2) b.ray(b.inBox(-0.99f, 0.99f), b.direction());
        else b.ray({0.f, 0.f, 3.9f}, Point3f(b.uniform(-1, 1), b.uniform(-1, 1), -1.f) - Point3f(0.f, 0.f, 3.9f));
    }
}

/// A displaced sphere of 10⁶ triangles (10⁵ with --quick), rays from around and inside it.
void largeMesh(Builder& b, bool quick) {
    const int nPhi = quick ? 250 : 1000, nTheta = quick ? 201 : 501;
    b.addMesh(Builder::sphereMesh(nTheta, nPhi, Point3f(0.f), [](float th, float ph) {
        return 1.f + 0.08f * std::sin(5.f * th) * std::cos(7.f * ph) + 0.02f * std::sin(41.f * th + 3.f * ph);
    }));
    const int rays = quick ? 10000 : 50000;
    for (int i = 0; i < rays; ++i) b.ray(b.inBox(-1.6f, 1.6f), b.direction());
    b.scene.referenceRays = quick ? 100 : 300;
    b.scene.large = true;
}

/// Constructive solid geometry (shape/csg, analytic to the accelerators): spheres with a
/// bite out of them, lenses, cubes pierced by capped cylinders and a nested csg tree,
/// among random triangles; random rays, 30 % with a finite tMax. What it probes: that
/// every accelerator culls a csg by its bounds (of the union, the intersection, the
/// minuend) without losing hits, and asks it the same questions.
void csgScene(Builder& b, bool quick) {
    using Params = std::vector<std::pair<std::string, PropertyValue>>;
    auto make = [&](const std::string& type, const Params& params) {
        Properties p("shape", type);
        for (const auto& [name, value] : params) p.set(name, value);
        return PropertyValue(ComponentValue{"shape", b.registry.create("shape", type, p)});
    };
    auto sphere = [&](Point3f c, float r) { return make("sphere", {{"center", PointValue{c}}, {"radius", double(r)}}); };
    auto csg = [&](const char* op, const std::vector<PropertyValue>& parts) {
        Params p{{"operation", std::string(op)}};
        for (std::size_t i = 0; i < parts.size(); ++i) p.emplace_back(fmt::format("p{}", i), parts[i]);
        return make("csg", p);
    };
    auto add = [&](const PropertyValue& v) {
        Ref<IShape> s = query<IShape>(std::get<ComponentValue>(v).object);
        if (!s) fail("accelerator suite: csg is not an IShape");
        b.add(s);
    };
    for (int i = 0; i < 3; ++i) {
        Point3f c = b.inBox(-0.8f, 0.8f);
        float r = b.logUniform(0.1f, 0.4f);
        add(csg("difference", {sphere(c, r), sphere(c + 0.8f * r * b.direction(), 0.6f * r)}));
        Point3f l = b.inBox(-0.8f, 0.8f);
        Vector3f off = 0.5f * r * b.direction();
        add(csg("intersection", {sphere(l - off, r), sphere(l + off, r)}));
    }
    for (int i = 0; i < 2; ++i) {
        Point3f c = b.inBox(-0.7f, 0.7f);
        float r = b.logUniform(0.1f, 0.3f);
        Vector3f axis = 1.4f * r * b.direction();
        add(csg("union", {make("cube", {{"to_world", Transform::translate(c) * Transform::rotate(b.direction(), b.uniform(0.f, 180.f)) *
                                                           Transform::scale(Vector3f(r))}}),
                          make("cylinder", {{"p0", PointValue{c - axis}}, {"p1", PointValue{c + axis}},
                                            {"radius", double(0.4f * r)}, {"caps", true}})}));
    }
    std::vector<PropertyValue> axes;
    Point3f c = b.inBox(-0.5f, 0.5f);
    for (int a = 0; a < 3; ++a) {
        Vector3f h(0.f);
        h[a] = 0.6f;
        axes.push_back(make("cylinder", {{"p0", PointValue{c - h}}, {"p1", PointValue{c + h}}, {"radius", 0.18}, {"caps", true}}));
    }
    add(csg("difference", {csg("intersection", {make("cube", {{"to_world", Transform::translate(c) * Transform::scale(Vector3f(0.4f))}}),
                                                sphere(c, 0.54f)}),
                           csg("union", axes)}));
    TriangleMesh m;
    for (int i = 0; i < 200; ++i) {
        Point3f q = b.inBox(-1.f, 1.f);
        float size = b.logUniform(0.02f, 0.3f);
        Builder::triangle(m, q + size * b.direction(), q + size * b.direction(), q + size * b.direction());
    }
    b.addMesh(std::move(m));
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Vector3f d = b.direction();
        float tMax = b.rng.nextFloat() < 0.3f ? b.uniform(0.05f, 3.f) : Infinity;
        b.ray(b.inBox(-1.5f, 1.5f), d, tMax);
    }
}

} // namespace

const std::vector<std::string>& accelSceneNames() {
    static const std::vector<std::string> names = {"soup",    "cornell",  "large mesh",         "scale 1e6",
                                                   "scale 1e-6", "slivers", "coplanar", "edges and vertices",
                                                   "on surface", "axis aligned", "tmax at hit", "grazing",
                                                   "csg"};
    return names;
}

AccelScene makeAccelScene(const std::string& name, Registry& registry, std::uint64_t seed, bool quick) {
    AccelScene scene;
    scene.name = name;
    std::uint64_t s = mixBits(seed ^ mixBits(fnv1a("accelerator scene/" + name)));
    Builder b{scene, registry, PCG32(s, mixBits(s + 1))};
    if (name == "soup") soup(b, quick, 1.f);
    else if (name == "cornell") cornell(b, quick);
    else if (name == "large mesh") largeMesh(b, quick);
    else if (name == "scale 1e6") soup(b, quick, 1e6f);
    else if (name == "scale 1e-6") soup(b, quick, 1e-6f);
    else if (name == "slivers") slivers(b, quick);
    else if (name == "coplanar") coplanar(b, quick);
    else if (name == "edges and vertices") edgesAndVertices(b, quick);
    else if (name == "on surface") onSurface(b, quick);
    else if (name == "axis aligned") axisAligned(b, quick);
    else if (name == "tmax at hit") tMaxAtHit(b, quick);
    else if (name == "grazing") grazing(b, quick);
    else if (name == "csg") csgScene(b, quick);
    else fail("accelerator suite: no scene '{}'", name);
    if (!scene.large) scene.referenceRays = scene.rays.size();
    std::size_t tris = 0;
    BBox3f box;
    for (const IShape* sh : scene.shapes) tris += sh->mesh() ? sh->mesh()->triangleCount() : 0, box.expand(sh->bbox());
    scene.triangles = tris;
    scene.extent = box.valid() ? glm::length(Vector3d(box.extents())) : 0.0;
    scene.description = fmt::format("{} shapes, {} triangles, {} analytic; {} rays", scene.shapes.size(), tris,
                                    std::count_if(scene.shapes.begin(), scene.shapes.end(),
                                                  [](const IShape* sh) { return !sh->mesh(); }),
                                    scene.rays.size());
    return scene;
}

} // namespace effigi::conform
