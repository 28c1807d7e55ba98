#pragma once
// Affine/projective 4x4 transforms with their inverse, Mitsuba's XML conventions:
// successive operations are multiplied on the left; lookat builds a camera-to-world
// matrix whose local +z looks at the target and local +x points left.
#include "effigi/math/vector.hpp"

#include <glm/gtc/matrix_inverse.hpp>

namespace effigi {

class Transform {
public:
    Transform() = default;
    explicit Transform(const glm::mat4& m) : m_m(m), m_inv(glm::inverse(m)) {}
    Transform(const glm::mat4& m, const glm::mat4& inv) : m_m(m), m_inv(inv) {}

    static Transform translate(const Vector3f& d);
    static Transform scale(const Vector3f& s);
    /// Rotation by angleDeg degrees about axis (right-handed).
    static Transform rotate(const Vector3f& axis, float angleDeg);
    static Transform lookAt(const Point3f& origin, const Point3f& target, const Vector3f& up);
    /// Perspective projection with the given field of view along y, near and far clip.
    static Transform perspective(float fovDeg, float near, float far);

    const glm::mat4& matrix() const { return m_m; }
    const glm::mat4& inverseMatrix() const { return m_inv; }
    Transform inverse() const { return Transform(m_inv, m_m); }

    /// this ∘ other: apply other first.
    Transform operator*(const Transform& o) const { return Transform(m_m * o.m_m, o.m_inv * m_inv); }

    Point3f point(const Point3f& p) const {
        glm::vec4 r = m_m * glm::vec4(p, 1.f);
        return r.w == 1.f ? Point3f(r) : Point3f(r) / r.w;
    }
    Vector3f vector(const Vector3f& v) const { return Vector3f(m_m * glm::vec4(v, 0.f)); }
    /// Normals transform with the inverse transpose.
    Normal3f normal(const Normal3f& n) const {
        return Normal3f(glm::transpose(m_inv) * glm::vec4(n, 0.f));
    }

    bool isFinite() const;
    bool isIdentity() const { return m_m == glm::mat4(1.f); }
    /// True when the transform mirrors space (negative determinant of the linear part).
    bool flipsHandedness() const { return glm::determinant(glm::mat3(m_m)) < 0.f; }

    bool operator==(const Transform& o) const { return m_m == o.m_m; }

private:
    glm::mat4 m_m{1.f};
    glm::mat4 m_inv{1.f};
};

} // namespace effigi
