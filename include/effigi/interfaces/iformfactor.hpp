#pragma once
// IFormFactor — form factors between the elements of an IMesh. F_ij is the fraction of
// the power leaving element i (uniform, Lambertian) that arrives directly at element j:
//
//   F_ij = 1/A_i ∫_{A_i} ∫_{A_j} cos θi cos θj / (π r²) · V(x, y) dA_y dA_x,
//
// with θ measured from each element's front normal (zero behind either element: elements
// are one-sided) and V the visibility through the scene's IIntersect. Properties every
// component must approximate: F_ij ≥ 0, reciprocity A_i F_ij = A_j F_ji, and Σ_j F_ij = 1
// for a closed enclosure (tests/test_formfactor.cpp checks them with Howell's catalogue).
// Reference: M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis",
// 1993, ch. 4; J. R. Howell, "A Catalog of Radiation Heat Transfer Configuration Factors".
#include "effigi/core/component.hpp"

#include <cstdint>
#include <span>

namespace effigi {

class IMesh;
class IShape;
class IIntersect;

struct FormFactorContext {
    const IMesh* mesh = nullptr;
    /// Every shape of the scene (occluders), indexed as the mesh's MeshElement::shape.
    std::span<const IShape* const> shapes;
    /// Visibility queries; null: nothing occludes (closed-form tests).
    const IIntersect* visibility = nullptr;
    /// Added to the seeds of stochastic components.
    std::uint64_t seed = 0;
};

class IFormFactor : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IFormFactor");
    static constexpr const char* Tag = "formfactor";

    /// Bind to a built mesh; called once before any query (the context must outlive them).
    virtual void prepare(const FormFactorContext& context) = 0;

    /// F_ij. Thread-safe; deterministic for a given seed.
    virtual double formFactor(std::uint32_t i, std::uint32_t j) const = 0;

    /// out[j] = F_ij for every element j (what i sends). The default calls formFactor in
    /// parallel; the hemi-cube computes a whole row at once. Thread-safe.
    virtual void row(std::uint32_t i, std::span<float> out) const;

    /// out[j] = F_ji for every element j (what each j receives from i: a shot of
    /// progressive refinement). The default calls formFactor(j, i) in parallel;
    /// components that compute rows use reciprocity, F_ji = F_ij A_i / A_j.
    virtual void column(std::uint32_t i, std::span<float> out) const;

    /// The context given to prepare().
    virtual const FormFactorContext& context() const = 0;
};

} // namespace effigi
