// TriangleMesh: transforming, flipping, validating. Everything here runs once per
// shape at load time, so clarity wins over speed.
#include "effigi/render/mesh.hpp"

#include "effigi/core/error.hpp"

namespace effigi {

namespace {

/// Cofactor matrix of the linear part: equals det(M) · M^{-T}, so it maps normals like
/// the inverse transpose but stays defined for singular M (a flattened shape).
glm::mat3 cofactor(const glm::mat3& m) {
    // Columns of the cofactor matrix are cross products of the columns of m.
    return glm::mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
}

bool finite2(const Point2f& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

} // namespace

void TriangleMesh::transform(const Transform& t) {
    if (t.isIdentity()) return;
    for (Point3f& p : positions) p = t.point(p);
    if (normals.empty()) return;
    glm::mat3 lin(t.matrix());
    float det = glm::determinant(lin);
    // det·M^{-T} flips normals when det < 0; undo that so normals keep their
    // orientation relative to the (mirrored) surface, like the inverse transpose does.
    glm::mat3 c = cofactor(lin) * (det < 0.f ? -1.f : 1.f);
    for (Normal3f& n : normals) {
        Normal3f m = c * n;
        float l2 = dot(m, m);
        n = l2 > 0.f && std::isfinite(l2) ? m / std::sqrt(l2) : Normal3f(0.f);
    }
}

void TriangleMesh::flip() {
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) std::swap(indices[i + 1], indices[i + 2]);
    for (Normal3f& n : normals) n = -n;
}

void TriangleMesh::validate(const std::string& what) const {
    if (indices.size() % 3 != 0)
        fail("{}: index count {} is not a multiple of 3", what, indices.size());
    if (positions.size() > std::size_t(0xffffffffu))
        fail("{}: too many vertices ({})", what, positions.size());
    if (!normals.empty() && normals.size() != positions.size())
        fail("{}: {} normals for {} vertices", what, normals.size(), positions.size());
    if (!uvs.empty() && uvs.size() != positions.size())
        fail("{}: {} texture coordinates for {} vertices", what, uvs.size(), positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (!isFinite(positions[i])) fail("{}: vertex {} has a non-finite position", what, i);
    for (std::size_t i = 0; i < normals.size(); ++i)
        if (!isFinite(normals[i])) fail("{}: vertex {} has a non-finite normal", what, i);
    for (std::size_t i = 0; i < uvs.size(); ++i)
        if (!finite2(uvs[i])) fail("{}: vertex {} has non-finite texture coordinates", what, i);
    for (const MeshAttribute& a : attributes) {
        std::size_t n = a.perFace ? triangleCount() : positions.size();
        if (a.data.size() != n * std::size_t(a.channels))
            fail("{}: attribute '{}' has {} values for {} {}s of {} channels", what, a.name, a.data.size(), n,
                 a.perFace ? "face" : "vertex", a.channels);
    }
    for (std::size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= positions.size())
            fail("{}: triangle {} uses vertex index {}, out of range (mesh has {} vertices)", what, i / 3,
                 indices[i], positions.size());
}

BBox3f TriangleMesh::bbox() const {
    BBox3f b;
    for (const Point3f& p : positions) b.expand(p);
    return b;
}

float TriangleMesh::triangleArea(std::size_t i) const {
    Point3f p0, p1, p2;
    triangle(i, p0, p1, p2);
    // In double: the squared length of a float cross product overflows for edges beyond
    // ~1e9, at the edge of the scene range (effigi/render/scene_range.hpp).
    return float(0.5 * glm::length(glm::cross(Vector3d(p1 - p0), Vector3d(p2 - p0))));
}

} // namespace effigi
