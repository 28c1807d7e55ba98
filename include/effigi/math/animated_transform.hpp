#pragma once
// A transform that moves with time: keyframes (time, matrix), interpolated as pbrt does —
// each key split into translation T, rotation R and stretch S (M = T·R·S, R and S from
// the polar decomposition of the linear part), then T and S interpolated linearly and R
// by spherical linear interpolation of its quaternion. Rigid motion stays rigid between
// keys (a lerp of matrices would shrink a spinning object); a rotation of more than 180°
// between two keys takes the short way round, so a spin needs a key every half turn or
// less (as in pbrt and Mitsuba 0.6). Before the first key and after the last the
// transform holds still.
// Reference: K. Shoemake, T. Duff, "Matrix animation and polar decomposition", Graphics
// Interface 1992; Pharr, Jakob, Humphreys, Physically Based Rendering, 3rd ed., §2.9.
#include "effigi/math/bbox.hpp"
#include "effigi/math/transform.hpp"

#include <glm/gtc/quaternion.hpp>

#include <vector>

namespace effigi {

class AnimatedTransform {
public:
    struct Key {
        float time;
        Transform transform;
    };

    /// The identity, still.
    AnimatedTransform() : AnimatedTransform(Transform()) {}
    /// A transform that does not move.
    explicit AnimatedTransform(const Transform& t);
    /// Keyframes in strictly increasing time (at least one; the caller checks the order).
    explicit AnimatedTransform(std::vector<Key> keys);

    bool isAnimated() const { return m_keys.size() > 1; }
    const std::vector<Key>& keys() const { return m_keys; }
    /// The transform at the first key (the pose "at rest").
    const Transform& first() const { return m_keys.front().transform; }

    /// The transform at `time` (its inverse computed too: non-finite for a singular pose).
    Transform at(float time) const;

    /// A box containing `b` moved by the transform over all time: the corners' positions
    /// at 32 instants between consecutive keys, grown by the largest step a corner makes
    /// between two instants (a corner's path between them stays within that distance of
    /// where it was for turns of up to 180° per key interval).
    BBox3f motionBounds(const BBox3f& b) const;

    bool operator==(const AnimatedTransform& o) const;

private:
    struct Decomposed {
        glm::vec3 translation;
        glm::quat rotation;
        glm::mat3 stretch;
    };
    static Decomposed decompose(const glm::mat4& m);

    std::vector<Key> m_keys;
    std::vector<Decomposed> m_parts;
};

} // namespace effigi
