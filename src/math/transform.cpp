#include "effigi/math/transform.hpp"

#include <glm/gtc/matrix_transform.hpp>

namespace effigi {

Transform Transform::translate(const Vector3f& d) {
    glm::mat4 m = glm::translate(glm::mat4(1.f), d);
    glm::mat4 inv = glm::translate(glm::mat4(1.f), -d);
    return Transform(m, inv);
}

Transform Transform::scale(const Vector3f& s) {
    glm::mat4 m = glm::scale(glm::mat4(1.f), s);
    glm::mat4 inv = glm::scale(glm::mat4(1.f), 1.f / s);
    return Transform(m, inv);
}

Transform Transform::rotate(const Vector3f& axis, float angleDeg) {
    glm::mat4 m = glm::rotate(glm::mat4(1.f), degToRad(angleDeg), normalize(axis));
    return Transform(m, glm::transpose(m));  // rotations are orthogonal
}

Transform Transform::lookAt(const Point3f& origin, const Point3f& target, const Vector3f& up) {
    // Columns: local +x = left, +y = up, +z = view direction, translation = origin.
    Vector3f dir = normalize(target - origin);
    Vector3f left = normalize(cross(normalize(up), dir));
    Vector3f newUp = cross(dir, left);
    glm::mat4 m(glm::vec4(left, 0.f), glm::vec4(newUp, 0.f), glm::vec4(dir, 0.f), glm::vec4(origin, 1.f));
    return Transform(m);
}

Transform Transform::perspective(float fovDeg, float near, float far) {
    // Camera space (+z forward) -> clip space with x, y scaled by the cotangent of half the
    // field of view and z mapped from [near, far] to [0, 1].
    float c = 1.f / std::tan(degToRad(0.5f * fovDeg));
    glm::mat4 m(0.f);
    m[0][0] = c;
    m[1][1] = c;
    m[2][2] = far / (far - near);
    m[3][2] = -near * far / (far - near);
    m[2][3] = 1.f;
    return Transform(m);
}

bool Transform::isFinite() const {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m_m[c][r]) || !std::isfinite(m_inv[c][r])) return false;
    return true;
}

} // namespace effigi
