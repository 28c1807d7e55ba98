// RIB geometry -> effigi shapes (RenderMan Interface 3.2, §5).
//
// Quadrics, with RenderMan's parameterisation (u sweeps θ from 0 to thetamax, v runs
// along the profile):
//   Sphere radius zmin zmax thetamax    whole (zmin <= -r, zmax >= r, 360°) -> sphere
//   Cylinder radius zmin zmax thetamax  360° -> cylinder from (0,0,zmin) to (0,0,zmax)
//   Disk height radius thetamax         360° -> disk, scaled by the radius at z = height
//   Cone height radius thetamax         always a mesh (effigi has no analytic cone)
// The sphere and cylinder are analytic only under a similarity transform (rotation,
// uniform scale, translation: what those shapes accept); partial sweeps, cut spheres and
// quadrics under other transforms become meshes of up to 64 segments around the full
// circle (32 from pole to pole) with the analytic normals.
// Polygon (convex: a fan), GeneralPolygon, PointsPolygons (convex: fans),
// PointsGeneralPolygons (ear clipping; one loop per polygon, holes are refused): "P", and
// optionally "N" (vertex normals; without them the faces are flat) and "st" (texture
// coordinates). Patch "bilinear" (4 points) and "bicubic" (16, in the current Basis,
// default Bezier): a 16 × 16 grid with the patch's normals; "st" gives the corners'
// texture coordinates. Every mesh keeps the current transformation as its to_world.
#include "state.hpp"
#include "tessellate.hpp"

#include "effigi/core/input.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace effigi::rib {

namespace {

constexpr double Pi = std::numbers::pi;  // in double, as the transformations are kept

bool isSimilarity(const glm::dmat4& m) {
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return false;
    double s2 = glm::dot(glm::dvec3(m[0]), glm::dvec3(m[0]));
    if (!(s2 > 0.0) || !std::isfinite(s2)) return false;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            if (std::abs(glm::dot(glm::dvec3(m[i]), glm::dvec3(m[j])) - (i == j ? s2 : 0.0)) > 1e-6 * s2) return false;
    return true;
}

ShapeSpec spec(State& s, Args& a) {
    ShapeSpec sp;
    sp.where = a.where();
    sp.label = a.label();
    sp.toWorld = s.attr.ctm;
    sp.material = s.attr.material;
    return sp;
}

void addAnalytic(State& s, Args& a, std::unique_ptr<xml::Node> n, const glm::dmat4& toWorld) {
    n->props.set("to_world", floatTransform(toWorld, a.where(), "the shape's transformation"), a.where());
    ShapeSpec sp = spec(s, a);
    sp.node = std::move(n);
    s.scene.shapes.push_back(std::move(sp));
}

/// The quadric's positional numbers (no parameters are supported on quadrics).
std::vector<double> quadricArgs(Args& a, std::size_t n) {
    std::vector<double> v = a.numbers(n);
    a.params().finish();
    return v;
}

double positive(Args& a, double v, const char* what) {
    if (!(v > 0.0)) a.fail("{} must be positive, got {}", what, v);
    return v;
}

/// thetamax in radians (sign kept), at most one turn.
double sweep(Args& a, double degrees) {
    if (!(std::abs(degrees) > 0.0)) a.fail("thetamax must not be 0 (the shape would be empty)");
    return std::copysign(std::min(std::abs(degrees), 360.0), degrees) * Pi / 180.0;
}

bool fullTurn(double theta) { return std::abs(theta) >= 2.0 * Pi; }
int around(double theta) { return std::max(3, int(std::ceil(64.0 * std::abs(theta) / (2.0 * Pi)))); }

} // namespace

void addMesh(State& s, Args& a, TriangleMesh m, bool faceNormals) {
    ShapeSpec sp = spec(s, a);
    orientTriangles(m, glm::determinant(glm::dmat3(sp.toWorld)) < 0.0);
    sp.mesh = std::move(m);
    sp.faceNormals = faceNormals;
    s.scene.shapes.push_back(std::move(sp));
}

void reqSphere(State& s, Args& a) {
    std::vector<double> v = quadricArgs(a, 4);
    const double r = positive(a, v[0], "the radius");
    const double zmin = std::clamp(std::min(v[1], v[2]), -r, r), zmax = std::clamp(std::max(v[1], v[2]), -r, r);
    if (!(zmax > zmin)) a.fail("zmin and zmax leave nothing of the sphere");
    const double theta = sweep(a, v[3]);
    if (zmin <= -r && zmax >= r && fullTurn(theta) && isSimilarity(s.attr.ctm)) {
        std::unique_ptr<xml::Node> n = makeNode("shape", "sphere", a.where());
        n->props.set("radius", r, a.where());
        return addAnalytic(s, a, std::move(n), s.attr.ctm);
    }
    const double phiMin = std::asin(zmin / r), phiMax = std::asin(zmax / r);
    const int nv = std::max(2, int(std::ceil(32.0 * (phiMax - phiMin) / Pi)));
    addMesh(s, a, gridMesh(around(theta), nv, [&](double u, double w, Vector3d& p, Vector3d& n) {
                const double t = u * theta, phi = phiMin + w * (phiMax - phiMin);
                n = Vector3d(std::cos(t) * std::cos(phi), std::sin(t) * std::cos(phi), std::sin(phi));
                p = r * n;
            }), false);
}

void reqCylinder(State& s, Args& a) {
    std::vector<double> v = quadricArgs(a, 4);
    const double r = positive(a, v[0], "the radius"), zmin = v[1], zmax = v[2];
    if (zmin == zmax) a.fail("zmin and zmax must differ (the cylinder would be empty)");
    const double theta = sweep(a, v[3]);
    if (fullTurn(theta) && isSimilarity(s.attr.ctm)) {
        std::unique_ptr<xml::Node> n = makeNode("shape", "cylinder", a.where());
        n->props.set("radius", r, a.where());
        n->props.set("p0", PointValue{Point3f(0.f, 0.f, float(zmin))}, a.where());
        n->props.set("p1", PointValue{Point3f(0.f, 0.f, float(zmax))}, a.where());
        return addAnalytic(s, a, std::move(n), s.attr.ctm);
    }
    addMesh(s, a, gridMesh(around(theta), 1, [&](double u, double w, Vector3d& p, Vector3d& n) {
                const double t = u * theta;
                n = Vector3d(std::cos(t), std::sin(t), 0.0);
                p = Vector3d(r * n.x, r * n.y, zmin + w * (zmax - zmin));
            }), false);
}

void reqCone(State& s, Args& a) {
    std::vector<double> v = quadricArgs(a, 3);
    const double h = v[0], r = positive(a, v[1], "the radius"), theta = sweep(a, v[2]);
    addMesh(s, a, gridMesh(around(theta), 1, [&](double u, double w, Vector3d& p, Vector3d& n) {
                const double t = u * theta, c = std::cos(t), sn = std::sin(t);
                p = Vector3d(r * (1.0 - w) * c, r * (1.0 - w) * sn, w * h);
                n = Vector3d(h * c, h * sn, r);
            }), false);
}

void reqDisk(State& s, Args& a) {
    std::vector<double> v = quadricArgs(a, 3);
    const double h = v[0], r = positive(a, v[1], "the radius"), theta = sweep(a, v[2]);
    if (fullTurn(theta)) {
        glm::dmat4 local = glm::scale(glm::translate(glm::dmat4(1.0), Vector3d(0.0, 0.0, h)), Vector3d(r, r, 1.0));
        return addAnalytic(s, a, makeNode("shape", "disk", a.where()), s.attr.ctm * local);
    }
    addMesh(s, a, gridMesh(around(theta), 1, [&](double u, double w, Vector3d& p, Vector3d& n) {
                const double t = u * theta;
                p = Vector3d(r * (1.0 - w) * std::cos(t), r * (1.0 - w) * std::sin(t), h);
                n = Vector3d(0.0, 0.0, 1.0);
            }), false);
}

namespace {

/// Polygons over the points "P" (with optional "N" and "st"), each face a list of point
/// indices.
void addPolygons(State& s, Args& a, Params& p, const std::vector<std::vector<std::uint32_t>>& faces, bool convex) {
    const std::vector<double>* P = p.numbers("P", 3);
    if (!P) a.fail("parameter 'P' is required");
    const std::size_t n = P->size() / 3;
    const std::vector<double>* N = p.numbers("N", 3);
    const std::vector<double>* st = p.numbers("st", 2);
    p.finish();
    if (N && N->size() != P->size()) a.fail("'N' has {} normals for {} points", N->size() / 3, n);
    if (st && st->size() / 2 != n) a.fail("'st' has {} pairs for {} points", st->size() / 2, n);
    TriangleMesh m;
    for (std::size_t i = 0; i < n; ++i) {
        m.positions.emplace_back((*P)[3 * i], (*P)[3 * i + 1], (*P)[3 * i + 2]);
        if (N) m.normals.emplace_back((*N)[3 * i], (*N)[3 * i + 1], (*N)[3 * i + 2]);
        if (st) m.uvs.emplace_back((*st)[2 * i], (*st)[2 * i + 1]);
    }
    for (const auto& f : faces) {
        if (f.size() < 3) a.fail("a polygon has {} vertices (at least 3 are needed)", f.size());
        for (std::uint32_t i : f)
            if (i >= n) a.fail("vertex index {} is out of range ('P' has {} points)", i, n);
        triangulate(m.positions, f, convex, m.indices);
    }
    addMesh(s, a, std::move(m), N == nullptr);
}

/// Faces from a count per face and the concatenated indices; the counts must use them all.
std::vector<std::vector<std::uint32_t>> split(Args& a, const std::vector<std::uint32_t>& counts,
                                              const std::vector<std::uint32_t>& indices) {
    std::vector<std::vector<std::uint32_t>> faces;
    std::size_t at = 0;
    for (std::uint32_t c : counts) {
        if (c > indices.size() - at) a.fail("the vertex counts add up to more than the {} indices given", indices.size());
        faces.emplace_back(indices.begin() + std::ptrdiff_t(at), indices.begin() + std::ptrdiff_t(at + c));
        at += c;
    }
    if (at != indices.size()) a.fail("the vertex counts add up to {}, but {} indices are given", at, indices.size());
    return faces;
}

std::vector<std::uint32_t> sequence(std::size_t n) {
    std::vector<std::uint32_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = std::uint32_t(i);
    return v;
}

void oneLoopEach(Args& a, const std::vector<std::uint32_t>& nloops) {
    for (std::uint32_t l : nloops)
        if (l != 1) a.fail("each polygon must have one loop (holes are not supported), got nloops = {}", l);
}

} // namespace

void reqPolygon(State& s, Args& a) {
    Params p = a.params();
    const std::vector<double>* P = p.numbers("P", 3);
    if (!P) a.fail("parameter 'P' is required");
    addPolygons(s, a, p, {sequence(P->size() / 3)}, true);
}

void reqGeneralPolygon(State& s, Args& a) {
    std::vector<std::uint32_t> nverts = a.integers("nverts");
    oneLoopEach(a, {std::uint32_t(nverts.size())});
    Params p = a.params();
    const std::vector<double>* P = p.numbers("P", 3);
    if (!P) a.fail("parameter 'P' is required");
    if (P->size() / 3 != nverts[0]) a.fail("'P' has {} points where {} are needed", P->size() / 3, nverts[0]);
    addPolygons(s, a, p, {sequence(nverts[0])}, false);
}

void reqPointsPolygons(State& s, Args& a) {
    std::vector<std::uint32_t> nverts = a.integers("nverts"), verts = a.integers("vertices");
    Params p = a.params();
    addPolygons(s, a, p, split(a, nverts, verts), true);
}

void reqPointsGeneralPolygons(State& s, Args& a) {
    std::vector<std::uint32_t> nloops = a.integers("nloops"), nverts = a.integers("nverts"),
                               verts = a.integers("vertices");
    oneLoopEach(a, nloops);
    if (nverts.size() != nloops.size()) a.fail("{} loop counts but {} vertex counts", nloops.size(), nverts.size());
    Params p = a.params();
    addPolygons(s, a, p, split(a, nverts, verts), false);
}

} // namespace effigi::rib
