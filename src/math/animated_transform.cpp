// AnimatedTransform (include/effigi/math/animated_transform.hpp): decomposition of each
// key into T·R·S and their interpolation.
#include "effigi/math/animated_transform.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

AnimatedTransform::AnimatedTransform(const Transform& t) : AnimatedTransform(std::vector<Key>{{0.f, t}}) {}

AnimatedTransform::AnimatedTransform(std::vector<Key> keys) : m_keys(std::move(keys)) {
    if (m_keys.empty()) m_keys.push_back({0.f, Transform()});
    for (const Key& k : m_keys) m_parts.push_back(decompose(k.transform.matrix()));
    // Consecutive quaternions in one hemisphere, so slerp turns the short way.
    for (std::size_t i = 1; i < m_parts.size(); ++i)
        if (glm::dot(m_parts[i - 1].rotation, m_parts[i].rotation) < 0.f) m_parts[i].rotation = -m_parts[i].rotation;
}

AnimatedTransform::Decomposed AnimatedTransform::decompose(const glm::mat4& m) {
    Decomposed d;
    d.translation = glm::vec3(m[3]);
    const glm::mat3 linear(m);
    // Polar decomposition by Newton's iteration R ← ½ (R + R^-T) (Higham 1986), which
    // converges quadratically to the orthogonal factor of an invertible matrix.
    glm::mat3 r = linear;
    for (int i = 0; i < 100; ++i) {
        const glm::mat3 next = 0.5f * (r + glm::transpose(glm::inverse(r)));
        float change = 0.f;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) change = std::max(change, std::abs(next[c][k] - r[c][k]));
        r = next;
        if (change < 1e-7f) break;
    }
    // A mirroring key keeps its reflection in the stretch, so R is a rotation.
    if (glm::determinant(r) < 0.f) r = -r;
    d.rotation = glm::normalize(glm::quat_cast(r));
    d.stretch = glm::inverse(r) * linear;
    return d;
}

Transform AnimatedTransform::at(float time) const {
    if (m_keys.size() == 1 || !(time > m_keys.front().time)) return m_keys.front().transform;
    if (time >= m_keys.back().time) return m_keys.back().transform;
    const auto it = std::upper_bound(m_keys.begin(), m_keys.end(), time,
                                     [](float t, const Key& k) { return t < k.time; });
    const std::size_t i = std::size_t(it - m_keys.begin()) - 1;
    const float u = (time - m_keys[i].time) / (m_keys[i + 1].time - m_keys[i].time);
    const Decomposed &a = m_parts[i], &b = m_parts[i + 1];
    const glm::vec3 t = glm::mix(a.translation, b.translation, u);
    const glm::quat r = glm::slerp(a.rotation, b.rotation, u);
    glm::mat3 s;
    for (int c = 0; c < 3; ++c) s[c] = glm::mix(a.stretch[c], b.stretch[c], u);
    glm::mat4 m(glm::mat3_cast(r) * s);
    m[3] = glm::vec4(t, 1.f);
    return Transform(m);
}

BBox3f AnimatedTransform::motionBounds(const BBox3f& b) const {
    auto corners = [&](const Transform& t, Point3f* out) {
        for (int c = 0; c < 8; ++c)
            out[c] = t.point(Point3f(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z));
    };
    BBox3f out;
    Point3f prev[8], cur[8];
    corners(first(), prev);
    for (const Point3f& p : prev) out.expand(p);
    float step = 0.f;
    constexpr int Steps = 32;
    for (std::size_t k = 0; k + 1 < m_keys.size(); ++k)
        for (int i = 1; i <= Steps; ++i) {
            const float t = m_keys[k].time + (m_keys[k + 1].time - m_keys[k].time) * float(i) / Steps;
            corners(at(t), cur);
            for (int c = 0; c < 8; ++c) {
                out.expand(cur[c]);
                step = std::max(step, length(cur[c] - prev[c]));
                prev[c] = cur[c];
            }
        }
    out.min -= Vector3f(step);
    out.max += Vector3f(step);
    return out;
}

bool AnimatedTransform::operator==(const AnimatedTransform& o) const {
    if (m_keys.size() != o.m_keys.size()) return false;
    for (std::size_t i = 0; i < m_keys.size(); ++i)
        if (m_keys[i].time != o.m_keys[i].time || !(m_keys[i].transform == o.m_keys[i].transform)) return false;
    return true;
}

} // namespace effigi
