#pragma once
// SpecularTransfer — extended form factors (Sillion & Puech 1989): light that leaves one
// element and reaches another by way of mirrors and glass. The radiosity pass of
// renderer `twopass` wraps its form-factor component in it, so that a mirror throws
// light into the room and a glass sphere casts a lit shadow with a caustic, instead of
// specular surfaces being black occluders.
//
//   F^s_ij = fraction of the power leaving element i that reaches element j after at
//            least one specular (delta) bounce,
//
// estimated for each element by `rays` cosine-distributed rays from uniform points of it
// (Malley's method: the fraction of such rays arriving is the form factor), followed
// through specular reflections and refractions (up to maxDepth bounces, the BSDF
// choosing reflection or refraction) until they land on the front of an element. The
// throughput is made grey: the mean over four stratified wavelengths (the hero alone
// after a dispersive refraction). The base component's form factors treat specular
// surfaces as occluders, so the two add without counting any light twice, and
// F_ij + F^s_ij is what the solver sees. Rows are stored sparse, with their transpose
// for columns (progressive refinement).
#include "effigi/interfaces/iformfactor.hpp"

#include <vector>

namespace effigi {

class SpecularTransfer final : public Implements<IFormFactor> {
public:
    SpecularTransfer(Ref<IFormFactor> base, int rays, int maxDepth);

    /// Prepares the base component, then traces the specular paths (needs visibility).
    void prepare(const FormFactorContext& context) override;
    double formFactor(std::uint32_t i, std::uint32_t j) const override;
    void row(std::uint32_t i, std::span<float> out) const override;
    void column(std::uint32_t i, std::span<float> out) const override;
    const FormFactorContext& context() const override { return m_ctx; }

    /// Number of stored extended form factors (non-zero pairs).
    std::size_t pairs() const { return m_rowValue.size(); }

private:
    Ref<IFormFactor> m_base;
    int m_rays, m_maxDepth;
    FormFactorContext m_ctx;
    // Compressed rows (i -> j, F^s_ij) and the same values by column (j -> i).
    std::vector<std::size_t> m_rowStart, m_colStart;
    std::vector<std::uint32_t> m_rowIndex, m_colIndex;
    std::vector<float> m_rowValue, m_colValue;
};

} // namespace effigi
