#pragma once
// Watertight ray/triangle intersection (Woop, Benthin & Wald 2013, "Watertight
// Ray/Triangle Intersection", JCGT 2(1)): rays through shared edges and vertices hit
// exactly one of the adjacent triangles, never none. Used by the reference accelerators.
#include "effigi/math/vector.hpp"

namespace effigi {

/// Precomputed per-ray shear (the ray is transformed so that it points along +z).
struct WatertightRay {
    Point3f o;
    int kx, ky, kz;
    float sx, sy, sz;

    WatertightRay(const Point3f& org, const Vector3f& d) : o(org) {
        Vector3f a = glm::abs(d);
        kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (d[kz] < 0.f) std::swap(kx, ky);  // keep the winding
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.f / d[kz];
    }
};

/// Hit in (0, tMax): t and barycentrics (b1, b2) of p1 and p2 (Embree's u, v).
inline bool intersectTriangle(const WatertightRay& r, const Point3f& p0, const Point3f& p1, const Point3f& p2,
                              float tMax, float& t, float& b1, float& b2) {
    Vector3f A = p0 - r.o, B = p1 - r.o, C = p2 - r.o;
    float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
    float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
    float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if (u == 0.f || v == 0.f || w == 0.f) {  // on an edge: decide in double precision
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
    float det = u + v + w;
    if (det == 0.f) return false;
    float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
    float T = u * az + v * bz + w * cz;
    // t = T / det must lie in (0, tMax); compare without dividing, respecting det's sign.
    if (det > 0.f ? (T <= 0.f || T > tMax * det) : (T >= 0.f || T < tMax * det)) return false;
    float inv = 1.f / det;
    t = T * inv;
    b1 = v * inv;
    b2 = w * inv;
    return true;
}

} // namespace effigi
