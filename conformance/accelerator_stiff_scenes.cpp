// The stiff scenes of the accelerator suite: slivers, coplanar and duplicate triangles,
// rays along edges and through vertices, rays leaving surfaces, axis-aligned rays, tMax at
// a hit distance, grazing rays (accelerator_builder.hpp). Each states what its rays probe.
#include "conformance/accelerator_builder.hpp"

#include "effigi/interfaces/iintersect.hpp"

#include <algorithm>
#include <numbers>

namespace effigi::conform {

/// Needles and slivers: two corners far apart, the third 1e-7 to 1e-3 of the length off
/// their line; rays aimed into them and random rays.
void slivers(Builder& b, bool quick) {
    const int n = quick ? 300 : 1000;
    TriangleMesh m;
    for (int i = 0; i < n; ++i) {
        Point3f c = b.inBox(-1.f, 1.f);
        Vector3f u = b.direction(), w = normalize(cross(u, b.direction()));
        float len = b.uniform(0.2f, 1.f);
        Point3f p0 = c - 0.5f * len * u, p1 = c + 0.5f * len * u;
        Point3f p2 = p0 + b.rng.nextFloat() * (p1 - p0) + len * b.logUniform(1e-7f, 1e-3f) * w;
        Builder::triangle(m, p0, p1, p2);
    }
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Point3f o = b.inBox(-1.5f, 1.5f);
        if (i % 10 < 7) {
            std::size_t t = std::min<std::size_t>(std::size_t(b.rng.nextFloat() * float(n)), std::size_t(n - 1));
            Point3f p0, p1, p2;
            m.triangle(t, p0, p1, p2);
            b.ray(o, b.interior(p0, p1, p2, 0.f) - o);
        } else {
            b.ray(o, b.direction());
        }
    }
    b.addMesh(std::move(m));
}

/// Overlapping triangles in the plane z = 0 (with duplicates in other vertex orders), in
/// x = 0.25 and in a tilted plane: every hit there is a tie.
void coplanar(Builder& b, bool quick) {
    TriangleMesh m[2];
    const int n = quick ? 80 : 200;
    auto inPlane = [&](int plane) -> Point3f {
        float u = b.uniform(-1, 1), v = b.uniform(-1, 1);
        if (plane == 0) return {u, v, 0.f};
        if (plane == 1) return {0.25f, u, v};
        Vector3f e1 = normalize(Vector3f(2, -1, 0)), e2 = normalize(cross(Vector3f(1, 2, 3), e1));
        return u * e1 + v * e2;
    };
    for (int i = 0; i < n; ++i) {
        int plane = i % 4 == 3 ? 2 : (i % 4 == 2 ? 1 : 0);
        Point3f p[3] = {inPlane(plane), inPlane(plane), inPlane(plane)};
        Builder::triangle(m[i % 2], p[0], p[1], p[2]);
        if (i % 5 == 0) Builder::triangle(m[(i + 1) % 2], p[1], p[2], p[0]);  // the same triangle again
        if (i % 7 == 0) Builder::triangle(m[i % 2], p[2], p[1], p[0]);        // and reversed
    }
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Point3f o = b.inBox(-1.5f, 1.5f);
        b.ray(o, inPlane(i % 3) - o);
    }
    for (auto& mesh : m) b.addMesh(std::move(mesh));
}

/// A non-planar height-field grid, a box and a tetrahedron (shared vertices); rays aimed
/// exactly at vertices, at points on edges, and along edges (lying in the planes of the
/// triangles that share them).
void edgesAndVertices(Builder& b, bool quick) {
    TriangleMesh grid;
    const int g = 12;
    for (int j = 0; j <= g; ++j)
        for (int i = 0; i <= g; ++i)
            grid.positions.push_back({-1.f + 2.f * float(i) / g, -1.f + 2.f * float(j) / g, 0.1f * b.rng.nextFloat()});
    for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
            auto v = std::uint32_t(j * (g + 1) + i), w = v + std::uint32_t(g + 1);
            grid.indices.insert(grid.indices.end(), {v, v + 1, w + 1, v, w + 1, w});
        }
    TriangleMesh box = Builder::box(Transform::translate({0.2f, -0.1f, 0.9f}) * Transform::rotate(normalize(Vector3f(1, 2, 3)), 30.f) *
                                    Transform::scale(Vector3f(0.3f)));
    TriangleMesh tet;
    tet.positions = {{-0.6f, 0.5f, 0.6f}, {-0.2f, 0.5f, 0.6f}, {-0.4f, 0.85f, 0.6f}, {-0.4f, 0.6f, 1.f}};
    tet.indices = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
    std::vector<std::pair<Point3f, Point3f>> edges;
    std::vector<Point3f> vertices;
    for (const TriangleMesh* m : {&grid, &box, &tet}) {
        vertices.insert(vertices.end(), m->positions.begin(), m->positions.end());
        for (std::size_t t = 0; t < m->triangleCount(); ++t)
            for (int k = 0; k < 3; ++k)
                edges.push_back({m->positions[m->indices[3 * t + std::size_t(k)]], m->positions[m->indices[3 * t + std::size_t(k + 1) % 3]]});
    }
    auto pick = [&](std::size_t size) { return std::min(std::size_t(b.rng.nextFloat() * float(size)), size - 1); };
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Point3f o(b.uniform(-1.5f, 1.5f), b.uniform(-1.5f, 1.5f), b.uniform(0.3f, 2.f));
        if (i % 8 == 7) o.z = -o.z;  // from below too
        const auto& [p, q] = edges[pick(edges.size())];
        switch (i % 4) {
        case 0: b.ray(o, vertices[pick(vertices.size())] - o); break;
        case 1: b.ray(o, p + b.rng.nextFloat() * (q - p) - o); break;
        case 2: b.ray(o, 0.5f * (p + q) - o); break;
        default: b.ray(p - b.uniform(0.05f, 1.f) * (q - p), q - p); break;
        }
    }
    b.addMesh(std::move(grid));
    b.addMesh(std::move(box));
    b.addMesh(std::move(tet));
}

/// Closed meshes (a sphere, a box) and a floor; rays leaving points on their triangles in
/// every direction, half starting exactly on the surface (rounded), half pushed off it by
/// offsetRayOrigin as the renderers do.
void onSurface(Builder& b, bool quick) {
    b.addMesh(Builder::sphereMesh(24, 40, Point3f(-0.3f, 0.f, 0.f), [](float, float) { return 0.7f; }));
    b.addMesh(Builder::box(Transform::translate({0.9f, 0.2f, 0.f}) * Transform::rotate(normalize(Vector3f(1, 1, 0)), 40.f) *
                           Transform::scale(Vector3f(0.3f))));
    TriangleMesh floor;
    Builder::triangle(floor, {-2, -2, -1}, {2, -2, -1}, {2, 2, -1});
    Builder::triangle(floor, {-2, -2, -1}, {2, 2, -1}, {-2, 2, -1});
    b.addMesh(std::move(floor));
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        const TriangleMesh& m = *b.scene.shapes[std::size_t(i % 3)]->mesh();
        std::size_t t = std::min(std::size_t(b.rng.nextFloat() * float(m.triangleCount())), m.triangleCount() - 1);
        Point3f p0, p1, p2;
        m.triangle(t, p0, p1, p2);
        Point3f p = b.interior(p0, p1, p2, 0.05f);
        Vector3f d = b.direction();
        b.ray(i % 2 ? p : offsetRayOrigin(p, normalize(cross(p1 - p0, p2 - p0)), d), d);
    }
}

/// Axis-aligned boxes and rectangles on a 1/64 lattice; directions with zero (and −0)
/// components, origins often exactly on face planes and edges of the lattice.
void axisAligned(Builder& b, bool quick) {
    auto snap = [](float x) { return std::round(x * 64.f) / 64.f; };
    for (int i = 0; i < 12; ++i) {
        Point3f lo(snap(b.uniform(-1, 0.6f)), snap(b.uniform(-1, 0.6f)), snap(b.uniform(-1, 0.6f)));
        Vector3f size(snap(b.uniform(0.1f, 0.4f)), snap(b.uniform(0.1f, 0.4f)), snap(b.uniform(0.1f, 0.4f)));
        b.addMesh(Builder::box(Transform::translate(lo + 0.5f * size) * Transform::scale(0.5f * size)));
    }
    TriangleMesh rects;
    for (int a = 0; a < 3; ++a) {
        float c = snap(b.uniform(-0.9f, 0.9f));
        Point3f q[4];
        for (int k = 0; k < 4; ++k) {
            q[k][a] = c;
            q[k][(a + 1) % 3] = k & 1 ? 0.75f : -0.75f;
            q[k][(a + 2) % 3] = k & 2 ? 0.75f : -0.75f;
        }
        Builder::triangle(rects, q[0], q[1], q[3]);
        Builder::triangle(rects, q[0], q[3], q[2]);
    }
    b.addMesh(std::move(rects));
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        Point3f o = b.inBox(-1.2f, 1.2f);
        for (int a = 0; a < 3; ++a)
            if (b.rng.nextFloat() < 0.5f) o[a] = snap(o[a]);
        Vector3f d(0.f);
        int axis = int(b.rng.nextUInt() % 3);
        float sign = b.rng.nextFloat() < 0.5f ? -1.f : 1.f;
        switch (i % 3) {
        case 0: d[axis] = sign; break;
        case 1:
            d[axis] = sign * b.uniform(0.2f, 1.f);
            d[(axis + 1) % 3] = b.uniform(-1.f, 1.f);
            d[(axis + 2) % 3] = -0.f;
            break;
        default:
            d = b.direction();
            d[axis] = sign > 0.f ? 0.f : -0.f;
            break;
        }
        b.ray(o, d);
    }
}

/// The soup's geometry; rays whose tMax is exactly a hit distance found by bruteforce,
/// one float ulp either side, and 1e-3 relative either side.
void tMaxAtHit(Builder& b, bool quick) {
    soup(b, quick, 1.f);
    std::vector<Ray> base = std::move(b.scene.rays);
    b.scene.rays.clear();
    Properties p("accelerator", "bruteforce");
    Ref<IIntersect> ref = query<IIntersect>(b.registry.create("accelerator", "bruteforce", p));
    if (!ref) fail("accelerator suite: bruteforce is not an IIntersect");
    ref->build(b.scene.shapes);
    const std::size_t want = quick ? 4000 : 20000;
    for (const Ray& r0 : base) {
        Ray r = r0;
        r.tMax = Infinity;
        Hit h;
        if (!ref->intersect(r, h)) continue;
        for (float tMax : {h.t, std::nextafter(h.t, Infinity), std::nextafter(h.t, 0.f), h.t * (1.f + 1e-3f), h.t * (1.f - 1e-3f)})
            b.ray(r.o, r.d, tMax);
        if (b.scene.rays.size() >= want) break;
    }
}

/// Large triangles in random orientations and a floor; rays hitting their interiors at
/// grazing angles, |cos θ| between 1e-3 and 1e-2 to the normal.
void grazing(Builder& b, bool quick) {
    TriangleMesh m;
    for (int i = 0; i < 30; ++i) {
        Point3f c = b.inBox(-1.f, 1.f);
        Vector3f n = b.direction(), e1 = normalize(cross(n, b.direction())), e2 = cross(n, e1);
        Point3f p[3];
        for (int k = 0; k < 3; ++k) {
            float a = 2.f * Pi * (float(k) + b.uniform(-0.2f, 0.2f)) / 3.f;
            p[k] = c + 0.8f * (std::cos(a) * e1 + std::sin(a) * e2);
        }
        Builder::triangle(m, p[0], p[1], p[2]);
    }
    Builder::triangle(m, {-2, -2, -1.2f}, {2, -2, -1.2f}, {2, 2, -1.2f});
    Builder::triangle(m, {-2, -2, -1.2f}, {2, 2, -1.2f}, {-2, 2, -1.2f});
    const int rays = quick ? 4000 : 20000;
    for (int i = 0; i < rays; ++i) {
        std::size_t t = std::min(std::size_t(b.rng.nextFloat() * float(m.triangleCount())), m.triangleCount() - 1);
        Point3f p0, p1, p2;
        m.triangle(t, p0, p1, p2);
        Vector3f n = normalize(cross(p1 - p0, p2 - p0)), tangent = normalize(cross(n, b.direction()));
        float c = b.logUniform(1e-3f, 1e-2f) * (b.rng.nextFloat() < 0.5f ? -1.f : 1.f);
        Vector3f d = c * n + std::sqrt(1.f - c * c) * tangent;
        Point3f q = b.interior(p0, p1, p2, 0.15f);
        b.ray(q - b.uniform(0.3f, 1.5f) * d, d);
    }
    b.addMesh(std::move(m));
}

} // namespace effigi::conform
