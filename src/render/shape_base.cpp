// ShapeBase (nested BSDF/emitter, to_world) and MeshShape (triangle meshes: hit
// reconstruction from barycentrics, area sampling).
#include "effigi/render/shape_base.hpp"

#include "effigi/math/warp_functions.hpp"

#include <algorithm>
#include <limits>

namespace effigi {

// ---------------------------------------------------------------------------------------
// ShapeBase

void ShapeBase::addCommonParams(Schema& s) {
    s.transform("to_world", "Object-to-world transform");
    s.child("bsdf", "bsdf", "Surface scattering (default: a diffuse BSDF)");
    s.child("emitter", "emitter", "Area emitter that makes this shape a light (optional)");
    s.child("medium", "interior", "Participating medium inside the surface (optional; a medium boundary)");
    s.child("medium", "exterior", "Participating medium outside the surface (optional; a medium boundary)");
    s.boolean("flip_normals", false, "Turn the surface inside out: normals point the other way");
}

ShapeBase::ShapeBase(const Properties& props) {
    if (props.has("to_world")) m_toWorld = props.getTransform("to_world");
    if (props.has("flip_normals")) m_flipNormals = props.getBool("flip_normals");
    m_bsdf = props.get<IBSDF>("bsdf");
    if (!m_bsdf) {
        m_defaultBsdf = true;
        Properties p("bsdf", "diffuse", props.where());
        m_bsdf = effigi::query<IBSDF>(Registry::instance().create("bsdf", "diffuse", p));
        if (!m_bsdf) failAt(props.where(), "{}: could not create the default diffuse BSDF", props.describe());
    }
    m_emitter = props.get<IEmitter>("emitter");
    if (m_emitter) m_emitterWhere = props.whereOf("emitter");
    m_interior = props.get<IMedium>("interior");
    m_exterior = props.get<IMedium>("exterior");
}

Point3f ShapeBase::objectPoint(const Point3f& p) const {
    // Double: a far-off shape's to_world cancels its large translation here.
    const glm::dmat4 inv(m_toWorld.inverseMatrix());
    const glm::dvec4 q = inv * glm::dvec4(Vector3d(p), 1.0);
    const Point3f o(Vector3d(q) / q.w);
    return isFinite(o) ? o : p;
}

LocalGeometry ShapeBase::localGeometry(const SurfaceInteraction& si) const {
    return LocalGeometry{objectPoint(si.p), Vector3f(0.f), Vector3f(0.f)};
}

void ShapeBase::attachEmitter() {
    if (!m_emitter) return;
    try {
        m_emitter->attach(this);
    } catch (const Error& e) {
        // attach() errors (e.g. a point light nested in a shape) know no file position.
        if (e.where().known() || !m_emitterWhere.known()) throw;
        throw Error(m_emitterWhere, e.what());
    }
}

// ---------------------------------------------------------------------------------------
// MeshShape

void MeshShape::addMeshParams(Schema& s) {
    if (!s.find("to_world")) addCommonParams(s);
    s.boolean("face_normals", false, "Ignore vertex normals: shade with the flat face normals");
}

MeshShape::MeshShape(const Properties& props) : ShapeBase(props) {
    if (props.has("face_normals")) m_faceNormals = props.getBool("face_normals");
}

namespace {

/// The unit normal along a triangle's edge cross product ng. The common case costs one
/// reciprocal and three products (this runs at every hit) and is inlined: passed by
/// value into a call, GCC assembles the vector from two stores and one load that fails
/// store forwarding (measured 1 % of a Cornell box render). A cross product whose squared
/// length overflows float (edges beyond ~1e9, the edge of the scene range of
/// scene_range.hpp) or underflows (edges below ~1e-10) is first divided by its largest
/// component, where squaring it directly would give a zero normal: a large emitter that
/// emits nothing.
[[gnu::noinline]] Normal3f unitNormalRescaled(Vector3f ng) {
    const float m = maxAbsComponent(ng);
    if (!(m > 0.f) || !std::isfinite(m)) return Normal3f(0.f, 0.f, 1.f);  // degenerate
    ng /= m;
    return ng * (1.f / std::sqrt(dot(ng, ng)));
}
[[gnu::always_inline]] inline Normal3f unitNormal(const Vector3f& ng) {
    const float ng2 = dot(ng, ng);
    if (ng2 >= std::numeric_limits<float>::min() && ng2 <= std::numeric_limits<float>::max()) [[likely]]
        return ng * (1.f / std::sqrt(ng2));
    return unitNormalRescaled(ng);
}

/// Smooth vertex normals for a mesh that has none: each triangle adds its unit normal
/// weighted by its angle at the vertex (Thürmer & Wüthrich 1998, "Computing vertex
/// normals from polygonal facets"), which does not depend on how a face is split into
/// triangles. Mitsuba 3 does the same for meshes without normals (unless face_normals).
void computeVertexNormals(TriangleMesh& m) {
    std::vector<Vector3d> acc(m.positions.size(), Vector3d(0.0));
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        const std::uint32_t* idx = &m.indices[3 * i];
        Vector3d p[3];
        for (int k = 0; k < 3; ++k) p[k] = Vector3d(m.positions[idx[k]]);
        Vector3d n = glm::cross(p[1] - p[0], p[2] - p[0]);
        double len = glm::length(n);
        if (!(len > 0.0)) continue;
        n /= len;
        for (int k = 0; k < 3; ++k) {
            Vector3d e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
            double l1 = glm::length(e1), l2 = glm::length(e2);
            if (!(l1 > 0.0 && l2 > 0.0)) continue;
            double angle = std::acos(std::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0, 1.0));
            acc[idx[k]] += angle * n;
        }
    }
    m.normals.resize(m.positions.size());
    for (std::size_t v = 0; v < acc.size(); ++v) {
        double len = glm::length(acc[v]);
        // A vertex of degenerate triangles only: zero, and interaction() falls back to
        // the face normal there.
        m.normals[v] = len > 0.0 ? Normal3f(acc[v] / len) : Normal3f(0.f);
    }
}

} // namespace

void MeshShape::setMesh(TriangleMesh mesh, const std::string& what) {
    // Unlocated errors get the <shape>'s place from the registry (Registry::create).
    mesh.validate(what);
    if (mesh.triangleCount() == 0) fail("{}: mesh has no triangles", what);
    if (m_faceNormals) mesh.normals.clear();
    mesh.transform(m_toWorld);
    mesh.validate(what + " after to_world");  // a non-finite or huge to_world shows up here
    if (m_flipNormals) mesh.flip();
    if (!m_faceNormals && mesh.normals.empty()) computeVertexNormals(mesh);
    m_mesh = std::move(mesh);

    // Cumulative areas summed in double so that a million small triangles do not drift.
    std::size_t n = m_mesh.triangleCount();
    m_areaCdf.resize(n);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        sum += double(m_mesh.triangleArea(i));
        m_areaCdf[i] = float(sum);
    }
    m_area = float(sum);
    m_bbox = m_mesh.bbox();
    attachEmitter();
}

const std::uint32_t* MeshShape::hitPoint(const Hit& hit, SurfaceInteraction& si) const {
    const std::uint32_t* idx = &m_mesh.indices[3 * std::size_t(hit.prim)];
    const Point3f& p0 = m_mesh.positions[idx[0]];
    const Point3f& p1 = m_mesh.positions[idx[1]];
    const Point3f& p2 = m_mesh.positions[idx[2]];
    const float b1 = hit.uv.x, b2 = hit.uv.y, b0 = 1.f - b1 - b2;
    // From the barycentrics rather than o + t·d: exact on the triangle's plane.
    si.p = b0 * p0 + b1 * p1 + b2 * p2;
    si.pScale = std::max({maxAbsComponent(p0), maxAbsComponent(p1), maxAbsComponent(p2)});
    si.t = hit.t;
    si.prim = hit.prim;
    si.primUV = hit.uv;
    si.uv = m_mesh.uvs.empty() ? Point2f(b1, b2)
                               : b0 * m_mesh.uvs[idx[0]] + b1 * m_mesh.uvs[idx[1]] + b2 * m_mesh.uvs[idx[2]];
    return idx;
}

SurfaceInteraction MeshShape::interaction(const Ray& ray, const Hit& hit) const {
    SurfaceInteraction si;
    const std::uint32_t* idx = hitPoint(hit, si);
    const Point3f& p0 = m_mesh.positions[idx[0]];
    const Point3f& p1 = m_mesh.positions[idx[1]];
    const Point3f& p2 = m_mesh.positions[idx[2]];
    const float b1 = hit.uv.x, b2 = hit.uv.y, b0 = 1.f - b1 - b2;
    si.n = unitNormal(cross(p1 - p0, p2 - p0));

    Normal3f ns = si.n;
    if (!m_mesh.normals.empty()) {
        Normal3f m = b0 * m_mesh.normals[idx[0]] + b1 * m_mesh.normals[idx[1]] + b2 * m_mesh.normals[idx[2]];
        float m2 = dot(m, m);
        if (m2 > 1e-20f && std::isfinite(m2)) ns = m * (1.f / std::sqrt(m2));
    }

    Vector3f s(0.f);
    if (!m_mesh.uvs.empty()) {
        // dp/du from the two edge equations dp_i2 = du_i2 dp/du + dv_i2 dp/dv (pbrt §6.5.3).
        const Point2f& t0 = m_mesh.uvs[idx[0]];
        const Point2f& t1 = m_mesh.uvs[idx[1]];
        const Point2f& t2 = m_mesh.uvs[idx[2]];
        Vector2f d02 = t0 - t2, d12 = t1 - t2;
        float det = d02.x * d12.y - d02.y * d12.x;
        if (std::abs(det) > 1e-12f) {
            const float invDet = 1.f / det;
            s = (d12.y * (p0 - p2) - d02.y * (p1 - p2)) * invDet;
            si.dpdu = s;
            si.dpdv = (d02.x * (p1 - p2) - d12.x * (p0 - p2)) * invDet;
        }
    } else {
        si.dpdu = p1 - p0;
        si.dpdv = p2 - p0;
    }
    // Gram-Schmidt against the shading normal; fall back to an arbitrary tangent.
    s -= ns * dot(ns, s);
    float s2 = dot(s, s);
    if (s2 > 1e-20f && std::isfinite(s2)) {
        s *= 1.f / std::sqrt(s2);
        si.shading = Frame(s, cross(ns, s), ns);
    } else {
        si.shading = Frame(ns);
    }
    finish(si, ray);
    return si;
}

LocalGeometry MeshShape::localGeometry(const SurfaceInteraction& si) const {
    LocalGeometry g = ShapeBase::localGeometry(si);
    if (m_mesh.normals.empty() || std::size_t(si.prim) >= m_mesh.triangleCount()) return g;  // flat faces
    const std::uint32_t* idx = &m_mesh.indices[3 * std::size_t(si.prim)];
    const Normal3f &n0 = m_mesh.normals[idx[0]], &n1 = m_mesh.normals[idx[1]], &n2 = m_mesh.normals[idx[2]];
    const float b1 = si.primUV.x, b2 = si.primUV.y, b0 = 1.f - b1 - b2;
    // The shading normal is m / |m| for the interpolated m (interaction()); where it fell
    // back to the face normal, the normal is constant over the triangle.
    const Normal3f m = b0 * n0 + b1 * n1 + b2 * n2;
    const float m2 = dot(m, m);
    if (!(m2 > 1e-20f) || !std::isfinite(m2)) return g;
    Vector3f dmdu, dmdv;
    if (!m_mesh.uvs.empty()) {
        // The same edge equations as dp/du, dp/dv in interaction() (pbrt §6.5.3), for n.
        const Point2f &t0 = m_mesh.uvs[idx[0]], &t1 = m_mesh.uvs[idx[1]], &t2 = m_mesh.uvs[idx[2]];
        const Vector2f d02 = t0 - t2, d12 = t1 - t2;
        const float det = d02.x * d12.y - d02.y * d12.x;
        if (!(std::abs(det) > 1e-12f)) return g;  // interaction() left dpdu, dpdv zero too
        const float invDet = 1.f / det;
        dmdu = (d12.y * (n0 - n2) - d02.y * (n1 - n2)) * invDet;
        dmdv = (d02.x * (n1 - n2) - d12.x * (n0 - n2)) * invDet;
    } else {
        dmdu = n1 - n0;  // uv = (b1, b2)
        dmdv = n2 - n0;
    }
    // ∂(m/|m|) = (∂m − n (n·∂m)) / |m|.
    const float invLen = 1.f / std::sqrt(m2);
    const Vector3f n = m * invLen;
    g.dndu = (dmdu - n * dot(n, dmdu)) * invLen;
    g.dndv = (dmdv - n * dot(n, dmdv)) * invLen;
    if (!isFinite(g.dndu) || !isFinite(g.dndv)) g.dndu = g.dndv = Vector3f(0.f);
    return g;
}

PositionSample MeshShape::samplePosition(const Point2f& u) const {
    PositionSample ps;
    std::size_t n = m_areaCdf.size();
    if (n == 0 || !(m_area > 0.f)) return ps;  // pdf 0: nothing to sample

    // Pick a triangle by area; upper_bound never lands on a zero-area triangle
    // (its cdf entry equals its predecessor's). In double: rounded to float, u.x·area
    // lands exactly on the triangle's lower cdf entry about once in 2^24/N samples (N
    // triangles), and the sample then sits on a vertex, where the surface has no normal.
    const double target = double(u.x) * double(m_area);
    std::size_t i = std::size_t(std::upper_bound(m_areaCdf.begin(), m_areaCdf.end(), target) - m_areaCdf.begin());
    if (i >= n) {  // u.x·area rounded up to the total: take the last triangle with area
        i = n - 1;
        while (i > 0 && m_areaCdf[i] == m_areaCdf[i - 1]) --i;
    }
    const double lo = i > 0 ? double(m_areaCdf[i - 1]) : 0.0, width = double(m_areaCdf[i]) - lo;
    // Reuse what is left of u.x inside the chosen triangle's interval.
    float ux = width > 0.0 ? float(std::clamp((target - lo) / width, 0.0, double(OneMinusEpsilon))) : 0.f;

    Point2f b = warp::squareToUniformTriangle(Point2f(ux, u.y));
    float b0 = b.x, b1 = b.y, b2 = 1.f - b0 - b1;
    const std::uint32_t* idx = &m_mesh.indices[3 * i];
    const Point3f& p0 = m_mesh.positions[idx[0]];
    const Point3f& p1 = m_mesh.positions[idx[1]];
    const Point3f& p2 = m_mesh.positions[idx[2]];
    ps.p = b0 * p0 + b1 * p1 + b2 * p2;
    ps.n = unitNormal(cross(p1 - p0, p2 - p0));
    ps.uv = m_mesh.uvs.empty()
                ? Point2f(b1, b2)
                : b0 * m_mesh.uvs[idx[0]] + b1 * m_mesh.uvs[idx[1]] + b2 * m_mesh.uvs[idx[2]];
    ps.pdf = 1.f / m_area;
    return ps;
}

} // namespace effigi
